#include "plant/dimav_plant.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "plant/angle_constants.hpp"
#include "plant/divergence_monitor.hpp"
#include "plant/ground_contact.hpp"
#include "plant/rk4.hpp"

namespace odonata::plant {
namespace {
// Longest averaging window: a wing slower than 2 Hz is averaged over 0.5 s.
constexpr double kMaxAveragingWindowS = 0.5;
// Wing 1 fore-left, 2 hind-left, 3 hind-right, 4 fore-right.
constexpr std::array<double, kWingCount> kSideSign = {1.0, 1.0, -1.0, -1.0};
constexpr std::array<bool, kWingCount> kIsHind = {false, true, true, false};

const PlantConfig& Validated(const PlantConfig& config) {
  const std::string problems = ValidatePlantConfig(config);
  if (!problems.empty()) throw PlantConfigError("invalid plant configuration:\n" + problems);
  return config;
}

double WrapPhase(double phase_rad) {
  const double wrapped = std::fmod(phase_rad, kTwoPi);
  return wrapped < 0.0 ? wrapped + kTwoPi : wrapped;
}

// Into (−π, π] for a difference of two angles in (−π, π] (one turn at most).
double WrapDifference(double d_rad) {
  if (d_rad > kPi) d_rad -= kTwoPi;
  if (d_rad < -kPi) d_rad += kTwoPi;
  return d_rad;
}
}  // namespace

Eigen::Vector4d InitialStrokePhases(const PlantConfig& config) {
  Eigen::Vector4d phase;
  for (int w = 0; w < kWingCount; ++w) {
    phase(w) = kIsHind[w] ? WrapPhase(config.fore_hind_phase_rad) : 0.0;
  }
  return phase;
}

DimavPlant::DimavPlant(const PlantConfig& config)
    : config_(Validated(config)),
      body_(config.mass_kg, config.inertia_kgm2.asDiagonal().toDenseMatrix(), config.gravity_mps2),
      sample_period_s_(1.0 / config.integration.sample_rate_hz),
      steps_per_sample_(StepsPerSample(config)),
      step_s_(sample_period_s_ / steps_per_sample_),
      averager_(step_s_, kMaxAveragingWindowS),
      beat_averager_(step_s_, kMaxAveragingWindowS) {
  wings_.reserve(kWingCount);
  for (int w = 0; w < kWingCount; ++w) {
    wings_.emplace_back(config.wing, config.air_density_kgpm3, config.integration.rotational_forces,
                        config.hinge_position_m[w], kSideSign[w]);
  }
  Reset(InitialCondition{});
}

CommandMatrix DimavPlant::ClampToLimits(const CommandMatrix& command) const {
  CommandMatrix c = command;
  for (int w = 0; w < kWingCount; ++w) {
    c.row(w) = c.row(w).cwiseMax(config_.limits.min).cwiseMin(config_.limits.max);
  }
  return c;
}

void DimavPlant::Reset(const InitialCondition& initial) {
  initial_ = initial;
  initial_.state.attitude.normalize();
  state_ = initial_.state;
  phase_rad_ = InitialStrokePhases(config_);
  applied_command_ = ClampToLimits(initial.prior_command);
  time_s_ = 0.0;
  previous_raw_roll_rad_ = RollPitchYaw(state_.attitude).x();
  unwrapped_roll_rad_ = previous_raw_roll_rad_;
  previous_raw_yaw_rad_ = RollPitchYaw(state_.attitude).z();
  unwrapped_yaw_rad_ = previous_raw_yaw_rad_;
  on_ground_ = false;
  stopped_ = false;
  reset_count_ = 0;
  divergence_message_.clear();
  PrimeForceHistory(applied_command_);
  UpdateOutput();
}

WingLoad DimavPlant::ComputeLoads(const CommandMatrix& command,
                                  const Eigen::Vector4d& stroke_phase_rad,
                                  const Eigen::Vector3d& velocity_body_mps,
                                  const Eigen::Vector3d& rate_body_radps,
                                  Eigen::Matrix<double, kWingCount, 3>* per_wing_force_n) const {
  WingLoad total;
  for (int w = 0; w < kWingCount; ++w) {
    const WingLoad load =
        wings_[w].Compute(command.row(w), stroke_phase_rad(w), velocity_body_mps, rate_body_radps);
    total.force_n += load.force_n;
    total.moment_nm += load.moment_nm;
    if (per_wing_force_n) per_wing_force_n->row(w) = load.force_n.transpose();
  }
  return total;
}

void DimavPlant::PrimeForceHistory(const CommandMatrix& command) {
  // Replays the last kMaxAveragingWindowS of flapping with the body held at its initial state, so
  // the averages are wing-beat means from the first sample on (the body's own averages are then
  // its initial state, with the replayed forces).
  averager_.Clear();
  beat_averager_.Clear();
  const int steps = static_cast<int>(std::ceil(kMaxAveragingWindowS / step_s_));
  Eigen::Matrix<double, kWingCount, 3> per_wing;
  for (int k = steps; k >= 1; --k) {
    const double age_s = (k - 0.5) * step_s_;
    Eigen::Vector4d phase;
    for (int w = 0; w < kWingCount; ++w) {
      phase(w) = phase_rad_(w) - kTwoPi * command(w, kFlapFrequency) * age_s;
    }
    ComputeLoads(command, phase, state_.velocity_body_mps, state_.rate_body_radps, &per_wing);
    WingForceXz xz;
    xz.col(0) = per_wing.col(0);
    xz.col(1) = per_wing.col(2);
    averager_.Push(xz);
    beat_averager_.Push(BeatSignals(xz));
  }
}

BeatVector DimavPlant::BeatSignals(const WingForceXz& step_mean_force_n) const {
  // Roll and yaw continue the unwrapped angles of the last sample, so a mean across ±π is the
  // mean of a continuous angle; the last step of a sample ends where the sample's output does.
  const Eigen::Vector3d rpy = RollPitchYaw(state_.attitude);
  BeatVector v;
  v.segment<3>(kBeatVx) = state_.velocity_body_mps;
  v.segment<3>(kBeatP) = state_.rate_body_radps;
  v(kBeatRoll) = unwrapped_roll_rad_ + WrapDifference(rpy.x() - previous_raw_roll_rad_);
  v(kBeatPitch) = rpy.y();
  v(kBeatYaw) = unwrapped_yaw_rad_ + WrapDifference(rpy.z() - previous_raw_yaw_rad_);
  v(kBeatFx) = step_mean_force_n.col(0).sum();
  v(kBeatFz) = step_mean_force_n.col(1).sum();
  return v;
}

void DimavPlant::AdvanceOneStep(const CommandMatrix& command) {
  Eigen::Vector4d omega_radps;
  for (int w = 0; w < kWingCount; ++w) omega_radps(w) = kTwoPi * command(w, kFlapFrequency);

  WingForceXz step_mean = WingForceXz::Zero();
  Eigen::Matrix<double, kWingCount, 3> per_wing;
  const bool clamped = initial_.clamped_body;
  auto rhs = [&](double tau_s, const RigidBodyVector& x, double weight) -> RigidBodyVector {
    const Eigen::Vector4d phase = phase_rad_ + omega_radps * tau_s;
    const WingLoad load =
        ComputeLoads(command, phase, x.segment<3>(7), x.segment<3>(10), &per_wing);
    step_mean.col(0) += weight * per_wing.col(0);
    step_mean.col(1) += weight * per_wing.col(2);
    if (clamped) return RigidBodyVector::Zero();
    return body_.Derivative(x, load.force_n, load.moment_nm);
  };
  const RigidBodyVector next = Rk4Step<kRigidBodyStateSize>(rhs, state_.Pack(), step_s_);
  state_ = RigidBodyState::Unpack(next);
  state_.attitude.normalize();
  on_ground_ = !clamped && ApplyGroundContact(config_.ground, &state_);
  for (int w = 0; w < kWingCount; ++w) phase_rad_(w) += omega_radps(w) * step_s_;
  averager_.Push(step_mean);
  beat_averager_.Push(BeatSignals(step_mean));
}

StepStatus DimavPlant::Step(const CommandMatrix& command) {
  if (!command.allFinite()) {
    throw std::invalid_argument("DimavPlant::Step: command contains a non-finite value");
  }
  if (stopped_) return StepStatus::kStopped;
  applied_command_ = ClampToLimits(command);
  const RigidBodyState last_good = state_;
  const Eigen::Vector4d last_phase = phase_rad_;
  for (int s = 0; s < steps_per_sample_; ++s) AdvanceOneStep(applied_command_);
  for (int w = 0; w < kWingCount; ++w) phase_rad_(w) = WrapPhase(phase_rad_(w));
  time_s_ += sample_period_s_;

  const std::string problem = CheckDivergence(config_.divergence, state_);
  if (problem.empty()) {
    UpdateOutput();
    return StepStatus::kOk;
  }
  char when[64];
  std::snprintf(when, sizeof when, "diverged at t = %.2f s: ", time_s_);
  if (config_.divergence.policy == DivergencePolicy::kStop) {
    divergence_message_ = when + problem + " (policy stop: holding the last finite state)";
    state_ = last_good;
    phase_rad_ = last_phase;
    time_s_ -= sample_period_s_;
    stopped_ = true;
    return StepStatus::kStopped;
  }
  const std::string message = when + problem + " (policy reset: back to the initial condition)";
  const int resets = reset_count_ + 1;
  const double t_s = time_s_;
  Reset(initial_);
  reset_count_ = resets;
  divergence_message_ = message;
  time_s_ = t_s;  // time keeps running across a reset
  output_.time_s = t_s;
  return StepStatus::kReset;
}

void DimavPlant::UpdateOutput() {
  const Eigen::Vector3d rpy = RollPitchYaw(state_.attitude);
  unwrapped_yaw_rad_ += WrapDifference(rpy.z() - previous_raw_yaw_rad_);
  previous_raw_yaw_rad_ = rpy.z();
  unwrapped_roll_rad_ += WrapDifference(rpy.x() - previous_raw_roll_rad_);
  previous_raw_roll_rad_ = rpy.x();

  Eigen::Vector4d window_s;
  for (int w = 0; w < kWingCount; ++w) {
    const double f = applied_command_(w, kFlapFrequency);
    window_s(w) = f > 0.0 ? 1.0 / f : averager_.max_window_s();
  }
  const WingForceXz mean = averager_.Average(window_s);

  output_.time_s = time_s_;
  output_.velocity_body_mps = state_.velocity_body_mps;
  output_.rate_body_radps = state_.rate_body_radps;
  output_.roll_rad = rpy.x();
  output_.pitch_rad = rpy.y();
  output_.yaw_rad = unwrapped_yaw_rad_;
  output_.position_m = state_.position_m;
  output_.force_x_n = mean.col(0);
  output_.force_z_n = mean.col(1);
  output_.on_ground = on_ground_;

  const double mean_frequency_hz = applied_command_.col(kFlapFrequency).mean();
  const double beat_s =
      mean_frequency_hz > 0.0 ? 1.0 / mean_frequency_hz : beat_averager_.max_window_s();
  const BeatVector beat = beat_averager_.Average(beat_s);
  BeatAverages& b = output_.beat;
  b.window_s = std::min(beat_s, beat_averager_.max_window_s());
  b.velocity_body_mps = beat.segment<3>(kBeatVx);
  b.rate_body_radps = beat.segment<3>(kBeatP);
  b.roll_rad = std::remainder(beat(kBeatRoll), kTwoPi);
  if (b.roll_rad <= -kPi) b.roll_rad += kTwoPi;  // (−π, π] like RollPitchYaw()
  b.pitch_rad = beat(kBeatPitch);
  b.yaw_rad = beat(kBeatYaw);
  b.force_x_n = beat(kBeatFx);
  b.force_z_n = beat(kBeatFz);
}

}  // namespace odonata::plant

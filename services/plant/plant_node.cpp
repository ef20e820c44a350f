#include "plant_node.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "bus/sample_fields.hpp"

namespace odonata::plant_service {
namespace {

int8_t StatusCode(pipeline::SampleStatus status) {
  switch (status) {
    case pipeline::SampleStatus::kOnGround:
      return odonata::plant_state_t::STATUS_ON_GROUND;
    case pipeline::SampleStatus::kReset:
      return odonata::plant_state_t::STATUS_RESET;
    case pipeline::SampleStatus::kDiverged:
      return odonata::plant_state_t::STATUS_DIVERGED;
    case pipeline::SampleStatus::kOk:
      break;
  }
  return odonata::plant_state_t::STATUS_OK;
}

std::string SetupKey(const std::string& name) { return name.empty() ? "default" : name; }

}  // namespace

odonata::plant_state_t ToStateMessage(const pipeline::PlantSample& sample) {
  const plant::PlantOutput& o = sample.output;
  odonata::plant_state_t m{};
  m.utime = bus::NowUtime();
  m.seq = sample.seq;
  m.command_seq = sample.command_seq;
  m.t_s = o.time_s;
  for (int i = 0; i < 3; ++i) {
    m.velocity_mps[i] = o.velocity_body_mps(i);
    m.rate_radps[i] = o.rate_body_radps(i);
    m.position_m[i] = o.position_m(i);
  }
  m.attitude_rad[0] = o.roll_rad;
  m.attitude_rad[1] = o.pitch_rad;
  m.attitude_rad[2] = o.yaw_rad;
  for (int w = 0; w < plant::kWingCount; ++w) {
    m.fx_n[w] = o.force_x_n(w);
    m.fz_n[w] = o.force_z_n(w);
  }
  m.status = StatusCode(sample.status);
  return m;
}

odonata::beat_state_t ToBeatStateMessage(const pipeline::PlantSample& sample,
                                         const pipeline::VehicleSetup& setup) {
  const plant::BeatAverages& b = sample.output.beat;
  const plant::CommandMatrix& c = sample.applied_command;
  odonata::beat_state_t m{};
  m.utime = bus::NowUtime();
  m.seq = sample.seq;
  m.command_seq = sample.command_seq;
  m.t_s = sample.output.time_s;
  m.window_s = b.window_s;
  for (int i = 0; i < 3; ++i) {
    m.velocity_mps[i] = b.velocity_body_mps(i);
    m.rate_radps[i] = b.rate_body_radps(i);
  }
  m.attitude_rad[0] = b.roll_rad;
  m.attitude_rad[1] = b.pitch_rad;
  m.attitude_rad[2] = b.yaw_rad;
  m.fx_total_n = b.force_x_n;
  m.fz_total_n = b.force_z_n;
  for (int w = 0; w < plant::kWingCount; ++w) {
    m.applied_beta_rad[w] = c(w, plant::kStrokePlaneAngle);
    m.applied_freq_hz[w] = c(w, plant::kFlapFrequency);
    m.applied_amp_rad[w] = c(w, plant::kStrokeAmplitude);
    m.applied_pitch_mean_rad[w] = c(w, plant::kPitchMean);
    m.applied_pitch_amp_rad[w] = c(w, plant::kPitchAmplitude);
    m.applied_phase_rad[w] = c(w, plant::kPitchPhase);
  }
  const std::vector<double> u =
      experiments::AppliedChannelValues(c, setup.trim_command(0, plant::kStrokeAmplitude));
  m.u_vertical_applied_rad = u[0];
  m.u_roll_applied_rad = u[1];
  m.u_pitch_applied_rad = u[2];
  m.u_yaw_applied_rad = u[3];
  m.attitude_hold = setup.attitude_hold ? 1 : 0;
  return m;
}

plant::CommandMatrix ToCommandMatrix(const odonata::wing_command_t& msg) {
  plant::CommandMatrix c;
  for (int w = 0; w < plant::kWingCount; ++w) {
    c(w, plant::kStrokePlaneAngle) = msg.beta_rad[w];
    c(w, plant::kFlapFrequency) = msg.freq_hz[w];
    c(w, plant::kStrokeAmplitude) = msg.amp_rad[w];
    c(w, plant::kPitchMean) = msg.pitch_mean_rad[w];
    c(w, plant::kPitchAmplitude) = msg.pitch_amp_rad[w];
    c(w, plant::kPitchPhase) = msg.phase_rad[w];
  }
  return c;
}

PlantNode::PlantNode(bus::BusNode& bus, const plant::PlantConfig& config,
                     pipeline::PlantSession::Mode mode, const std::string& setup_name)
    : bus_(bus), config_(config), session_(config_, mode, Setup(setup_name)) {
  const auto& ch = bus_.channels();
  bus_.Subscribe<odonata::wing_command_t>(ch.command, [this](const auto& m) { OnCommand(m); });
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
  if (mode == pipeline::PlantSession::Mode::kLockstep) {
    bus_.Every(kInitialStatePeriodMs, [this] {
      if (!session_.commanded()) Publish(session_.last());
    });
  } else {
    const auto period = std::chrono::microseconds(
        static_cast<int64_t>(1e6 / config_.integration.sample_rate_hz + 0.5));
    bus_.Every(period, [this] { Publish(session_.Tick()); });
  }
  bus_.SetState(mode == pipeline::PlantSession::Mode::kLockstep ? "waiting" : "running");
  Publish(session_.last());
}

const pipeline::VehicleSetup& PlantNode::Setup(const std::string& name) {
  const std::string key = SetupKey(name);
  auto it = setups_.find(key);
  if (it == setups_.end()) {
    it = setups_.emplace(key, pipeline::VehicleSetupByName(key, config_)).first;
  }
  return it->second;
}

void PlantNode::OnCommand(const odonata::wing_command_t& msg) {
  // Thrown errors are counted as dropped and reported once per kind by BusNode.
  if (!bus::AllFinite(msg)) throw std::invalid_argument("command with NaN or Inf fields");
  const std::string count = bus::CountProblems(msg);
  if (!count.empty()) throw std::invalid_argument("command: " + count);

  const pipeline::CommandOutcome out = session_.Submit(msg.seq, ToCommandMatrix(msg));
  switch (out.verdict) {
    case pipeline::CommandVerdict::kRejected:
      ++bus_.stats().dropped;
      bus_.Report("command rejected", out.problem);
      return;
    case pipeline::CommandVerdict::kStale:
      ++bus_.stats().dropped;
      bus_.Report("stale command", out.problem);
      return;
    default:
      break;
  }
  if (out.missing > 0) {
    bus_.stats().gaps += out.missing;
    bus_.Report("gap in commands", "missing command seq " + std::to_string(msg.seq - out.missing) +
                                       " … " + std::to_string(msg.seq - 1));
  }
  if (out.superseded_unapplied) {
    ++bus_.stats().skipped;
    bus_.Report("command never applied",
                "command seq " + std::to_string(msg.seq - 1 - out.missing) +
                    " was replaced before a sample applied it (the sample clock fell behind)");
  }
  bus_.stats().repeated += out.extra_applications;
  if (session_.mode() == pipeline::PlantSession::Mode::kLockstep) bus_.SetState("running");
  if (out.publish) Publish(*out.publish);
}

void PlantNode::OnControl(const odonata::control_t& msg) {
  if (!bus_.AcceptControl(msg)) return;
  switch (msg.command) {
    case odonata::control_t::RESET:
      Reset(msg.path.empty() ? session_.setup().name : msg.path);
      break;
    case odonata::control_t::SHUTDOWN:
      bus_.Stop(0);
      break;
    default:
      break;  // the identifier's commands (freeze, save, …) are not for the plant
  }
}

void PlantNode::Reset(const std::string& setup_name) {
  const pipeline::VehicleSetup& setup = Setup(setup_name);  // throws for an unknown preset
  session_.Reset(setup);
  diverged_reported_ = false;
  std::fprintf(stderr, "[%s] reset to the initial condition of %s\n",
               bus_.options().instance.c_str(), setup.name.c_str());
  if (std::isfinite(setup.damage.at_s)) {
    std::fprintf(stderr,
                 "[%s] this run damages the vehicle: from t = %.3g s wing %s flies %.3g of the "
                 "commanded stroke amplitude and %.3g of the frequency\n",
                 bus_.options().instance.c_str(), setup.damage.at_s,
                 setup.damage.wing == 0 ? "every" : std::to_string(setup.damage.wing).c_str(),
                 setup.damage.amplitude_scale, setup.damage.frequency_scale);
  }
  bus_.SetState(session_.mode() == pipeline::PlantSession::Mode::kLockstep ? "waiting" : "running");
  Publish(session_.last());
}

void PlantNode::Publish(const pipeline::PlantSample& sample) {
  if (sample.status == pipeline::SampleStatus::kReset) {
    bus_.Report("plant diverged and reset", session_.plant().divergence_message());
  } else if (sample.status == pipeline::SampleStatus::kDiverged && !diverged_reported_) {
    diverged_reported_ = true;
    bus_.Report("plant diverged and stopped", session_.plant().divergence_message());
    bus_.SetState("error");
  }
  bus_.Publish(bus_.channels().state, ToStateMessage(sample));
  // Beside it, never instead of it: consumers of DIMAV_STATE are untouched.
  bus_.Publish(bus_.channels().beat_state, ToBeatStateMessage(sample, session_.setup()));
}

}  // namespace odonata::plant_service

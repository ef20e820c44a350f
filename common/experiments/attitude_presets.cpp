// The paper's free-flight experiments (section IV-B): vertical velocity under φ₀ on all four
// wings, and roll, pitch and yaw under differential commands, the onboard attitude hold on; and
// the held-vehicle variants of roll and pitch, which fly the same runs. Each preset's table entry
// and its excitation, together.

#include <algorithm>
#include <cmath>
#include <string>

#include "experiments/preset_kit.hpp"
#include "plant/angle_constants.hpp"
#include "signals/chirp.hpp"
#include "signals/gaussian_noise.hpp"

namespace odonata::experiments {
namespace {

using plant::CommandMatrix;
using plant::kRadPerDeg;
using plant::kStrokeAmplitude;
using plant::kStrokePlaneAngle;

void VerticalChirpAndNoise(const ExcitationContext& x, RunBuilder& b) {
  const Phase phase = x.phase;
  const double a0 = x.a0;
  // φ₀ ≈ 1.03 rad at the centre, 1.48 rad (85°) at the limit: the chirp and the noise, cut at
  // ±2.5σ (0.26 rad at 0.01 W), must share the 0.45 rad between.
  const double amplitude_rad =
      phase == Phase::kTrain ? 0.19 : (phase == Phase::kSelect ? 0.18 : 0.17);
  // Lift ∝ φ₀²: centring on φ₀c = √(φ₀² − E[u²]) keeps the mean lift at the weight.
  const double mean_square = 0.5 * amplitude_rad * amplitude_rad + kNoisePowerW;
  const double centre_rad = std::sqrt(a0 * a0 - mean_square);
  const signals::LinearChirp c_train(0.05, 5.0, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LinearChirp c_select(0.06, 5.5, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LogChirp c_val(0.05, 6.0, amplitude_rad, x.t_end_s, x.phase0);
  signals::GaussianNoise noise(kNoisePowerW, NoiseSeed(x.seed, phase), kNoiseClipSigmas);
  b.Fill(
      x.samples, x.dt_s,
      [&](double t, CommandMatrix* c) {
        const double u = ByPhase(phase, c_train, c_select, c_val, t) + noise.Next();
        c->col(kStrokeAmplitude).setConstant(centre_rad + u);
      },
      [&](const CommandMatrix& c) { return VerticalChannelRad(c, a0); }, "u_vertical_rad");
}

// Roll (left against right) or pitch (front against back): inverse φ₀ chirps. Bands stay well
// below the wing beat (≈ 5.4 Hz): a φ₀ modulation near f beats with the stroke's odd harmonics
// and rectifies into a steady moment the wing-beat-mean model cannot represent (it tumbled the
// vehicle in simulation).
void DifferentialAmplitude(const ExcitationContext& x, RunBuilder& b, bool roll) {
  const Phase phase = x.phase;
  const double a0 = x.a0;
  const double train_deg = roll ? 3.0 : 1.0, select_deg = roll ? 4.0 : 1.25,
               val_deg = roll ? 5.0 : 1.5;
  const double amplitude_rad =
      (phase == Phase::kTrain ? train_deg : (phase == Phase::kSelect ? select_deg : val_deg)) *
      kRadPerDeg;
  const signals::LinearChirp c_train(0.1, 3.0, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LinearChirp c_select(0.12, 3.5, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LogChirp c_val(0.15, 4.0, amplitude_rad, x.t_end_s, x.phase0);
  const int* plus = roll ? kLeft : kFront;
  const int* minus = roll ? kRight : kBack;
  b.Fill(
      x.samples, x.dt_s,
      [&](double t, CommandMatrix* c) {
        const double u = x.Fade(t) * ByPhase(phase, c_train, c_select, c_val, t);
        for (int i = 0; i < 2; ++i) {
          (*c)(plus[i], kStrokeAmplitude) = a0 + u;
          (*c)(minus[i], kStrokeAmplitude) = a0 - u;
        }
      },
      [roll](const CommandMatrix& c) { return roll ? RollChannelRad(c) : PitchChannelRad(c); },
      roll ? "u_roll_rad" : "u_pitch_rad");
}

void OppositeStrokePlanes(const ExcitationContext& x, RunBuilder& b) {
  const Phase phase = x.phase;
  const double amplitude_rad =
      (phase == Phase::kTrain ? 20.0 : (phase == Phase::kSelect ? 17.5 : 15.0)) * kRadPerDeg;
  const signals::LinearChirp c_train(0.2, 4.0, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LinearChirp c_select(0.25, 4.5, amplitude_rad, x.t_end_s, x.phase0);
  const signals::LogChirp c_val(0.3, 5.0, amplitude_rad, x.t_end_s, x.phase0);
  b.Fill(
      x.samples, x.dt_s,
      [&](double t, CommandMatrix* c) {
        const double u = x.Fade(t) * ByPhase(phase, c_train, c_select, c_val, t);
        for (int i = 0; i < 2; ++i) {
          (*c)(kLeft[i], kStrokePlaneAngle) = -u;
          (*c)(kRight[i], kStrokePlaneAngle) = u;
        }
      },
      YawChannelRad, "u_yaw_rad");
}

}  // namespace

std::vector<ExperimentPreset> AttitudePresets() {
  std::vector<ExperimentPreset> v;
  {
    ExperimentPreset p = Attitude("vertical_velocity", "vz_mps", "u_vertical_applied_rad", 0.05,
                                  "0.05", 41, "good (figure only)");
    p.ny = 2;
    p.train_duration_s = 40.0;
    p.validate_duration_s = 40.0;
    p.select_duration_s = 40.0;
    p.description = "body vertical velocity under the same phi0 on all four wings";
    p.train_excitation =
        "all wings: phi0 = phi0c + u, u = 0.19 rad linear chirp(0.05->5 Hz) + Gaussian noise "
        "0.01 W cut at 2.5 sigma; f = trim; attitude hold on";
    p.validate_excitation =
        "all wings: phi0 = phi0c + u, u = 0.17 rad log-chirp(0.05->6 Hz) + Gaussian noise 0.01 W "
        "cut at 2.5 sigma (other stream); f = trim; attitude hold on";
    p.select_excitation =
        "all wings: phi0 = phi0c + u, u = 0.18 rad linear chirp(0.06->5.5 Hz) + Gaussian noise "
        "0.01 W cut at 2.5 sigma (a third stream); f = trim; attitude hold on";
    p.excite = VerticalChirpAndNoise;
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Attitude("roll", "roll_rad", "u_roll_applied_rad", 0.01, "0.01", 6, "92.5 % validation");
    p.description =
        "roll under inverse phi0 chirps, left (1, 2) against right (3, 4); input: the applied "
        "differential, hold included (open loop)";
    p.train_excitation =
        "phi0 = trim +/- u (left +, right -), u = 3 deg linear chirp(0.1->3 Hz), 1 s fades; "
        "attitude hold on";
    p.validate_excitation =
        "phi0 = trim +/- u (left +, right -), u = 5 deg log-chirp(0.15->4 Hz), 1 s fades; "
        "attitude hold on";
    p.select_excitation =
        "phi0 = trim +/- u (left +, right -), u = 4 deg linear chirp(0.12->3.5 Hz), 1 s fades; "
        "attitude hold on";
    p.excite = [](const ExcitationContext& x, RunBuilder& b) { DifferentialAmplitude(x, b, true); };
    v.push_back(p);
  }
  {
    ExperimentPreset p = Attitude("pitch", "pitch_rad", "u_pitch_applied_rad", 0.001, "0.001", 3,
                                  "\"reasonably good\"");
    p.description =
        "pitch under front (1, 4) against back (2, 3) differences in amplitude; input: the "
        "applied differential, hold included (open loop)";
    p.train_excitation =
        "front: phi0 = trim + u; back: phi0 = trim - u; u = 1 deg linear chirp(0.1->3 Hz), 1 s "
        "fades; attitude hold on (no f differential: it drifts the fore/hind phase)";
    p.validate_excitation =
        "same mapping, u = 1.5 deg log-chirp(0.15->4 Hz), 1 s fades; attitude hold on";
    p.select_excitation =
        "same mapping, u = 1.25 deg linear chirp(0.12->3.5 Hz), 1 s fades; attitude hold on";
    p.excite = [](const ExcitationContext& x, RunBuilder& b) {
      DifferentialAmplitude(x, b, false);
    };
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Attitude("yaw", "yaw_rad", "u_yaw_applied_rad", 0.25, "0.25", 34, "about 98 %");
    p.description =
        "yaw under opposite stroke-plane angles, left (1, 2) -u against right (3, 4) +u; input: "
        "the applied differential (the hold does not act on beta)";
    p.train_excitation =
        "beta = -u left, +u right, u = 20 deg linear chirp(0.2->4 Hz), 1 s fades; attitude hold on";
    p.validate_excitation =
        "beta = -u left, +u right, u = 15 deg log-chirp(0.3->5 Hz), 1 s fades; attitude hold on";
    p.select_excitation =
        "beta = -u left, +u right, u = 17.5 deg linear chirp(0.25->4.5 Hz), 1 s fades; attitude "
        "hold on";
    p.excite = OppositeStrokePlanes;
    v.push_back(p);
  }
  // The held vehicle: the same runs (the base preset's excitation), identified from the
  // excitation before the hold adds its correction (the model then includes the hold). Yaw and
  // vertical velocity have no such variant: the hold acts on neither channel, so their
  // excitation is what the wings did.
  for (const char* base : {"roll", "pitch"}) {
    ExperimentPreset p = *std::find_if(
        v.begin(), v.end(), [base](const ExperimentPreset& q) { return q.name == base; });
    p.name += "_held";
    p.input_columns = {std::string("u_") + base + "_rad"};
    p.held_vehicle = true;
    p.description = std::string("HELD VEHICLE (closed loop, attitude hold inside the model): ") +
                    base + " from the excitation before the hold; runs as " + base;
    v.push_back(p);
  }
  return v;
}

}  // namespace odonata::experiments

// Experiments beyond the paper, where the physics is nonlinear (docs/identifier.md §11): the
// vertical velocity over a wide operating range, a static force map, roll with the coupled
// lateral state; and the damage scenarios, whose vehicle changes halfway through the validation
// run. Each preset's table entry and its excitation, together.

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "experiments/preset_kit.hpp"
#include "plant/angle_constants.hpp"
#include "signals/aprbs.hpp"
#include "signals/chirp.hpp"
#include "signals/multisine.hpp"

namespace odonata::experiments {
namespace {

using plant::CommandMatrix;
using plant::kFlapFrequency;
using plant::kPi;
using plant::kRadPerDeg;
using plant::kStrokeAmplitude;
using plant::kStrokePlaneAngle;

// f and φ₀ of all four wings at random held levels (APRBS); with `chirp_validation`, the
// validation run is a different family (slow log chirps). Faded in from hover trim.
void WideRange(const ExcitationContext& x, RunBuilder& b, bool chirp_validation) {
  const Phase phase = x.phase;
  const double a0 = x.a0;
  const plant::TrimResult& trim = x.trim;
  // Ranges inside the limits (f ≤ 8 Hz, φ₀ ≤ 85°) with room for the hold's φ₀ differential.
  constexpr double kFLow = 4.6, kFHigh = 6.6;
  constexpr double kALow = 38.0 * kRadPerDeg, kAHigh = 84.0 * kRadPerDeg;
  std::vector<double> f, a;
  if (phase == Phase::kValidate && chirp_validation) {
    const signals::LogChirp f_chirp(0.02, 0.6, 0.95 * 0.5 * (kFHigh - kFLow), x.t_end_s, x.phase0);
    const signals::LogChirp a_chirp(0.03, 1.0, 0.95 * 0.5 * (kAHigh - kALow), x.t_end_s, x.phase1);
    for (std::size_t k = 0; k < x.samples; ++k) {
      const double t = static_cast<double>(k) * x.dt_s;
      f.push_back(0.5 * (kFLow + kFHigh) + f_chirp.Value(t));
      a.push_back(0.5 * (kALow + kAHigh) + a_chirp.Value(t));
    }
  } else {
    const bool train = phase == Phase::kTrain;
    const int hold_min = train ? 30 : 25, hold_max = train ? 200 : 160;
    f = signals::AprbsSequence(x.samples, {kFLow, kFHigh, hold_min, hold_max},
                               AprbsSeed(x.seed, phase, 1));
    a = signals::AprbsSequence(x.samples, {kALow, kAHigh, hold_min, hold_max},
                               AprbsSeed(x.seed, phase, 2));
  }
  const double dt_s = x.dt_s;
  b.Fill(
      x.samples, dt_s,
      [&](double t, CommandMatrix* c) {
        // Fade in from hover trim over kRampS so every run starts in the air at rest.
        const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
        const double w = std::min(1.0, t / kRampS);
        c->col(kFlapFrequency).setConstant(trim.freq_hz + w * (f[k] - trim.freq_hz));
        c->col(kStrokeAmplitude).setConstant(a0 + w * (a[k] - a0));
      },
      [&](const CommandMatrix& c) { return VerticalChannelRad(c, a0); }, "u_vertical_rad");
  b.AddExcitation("u_freq_hz", MeanFrequencyHz);
}

// Levels change only at multiples of the decimation block, so each decimated row's input is one
// level and the next row's output its settled beat mean: y(j + 1) = g(u(j)).
void ForceMapLevels(const ExcitationContext& x, RunBuilder& b) {
  const Phase phase = x.phase;
  const int block = x.preset.decimate;
  const double lows[3] = {4.5, 25.0 * kRadPerDeg, -25.0 * kRadPerDeg};
  const double highs[3] = {7.5, 84.9 * kRadPerDeg, 25.0 * kRadPerDeg};
  const double bands[3][2] = {{0.01, 0.5}, {0.02, 1.2}, {0.015, 0.8}};
  std::vector<double> level[3];
  for (int i = 0; i < 3; ++i) {
    if (phase == Phase::kValidate) {
      const signals::LogChirp chirp(bands[i][0], bands[i][1], 0.5 * (highs[i] - lows[i]), x.t_end_s,
                                    RandomPhaseRad(x.seed, phase, 10 + i));
      for (std::size_t k = 0; k < x.samples; ++k) {
        const std::size_t start = k - k % static_cast<std::size_t>(block);
        level[i].push_back(0.5 * (lows[i] + highs[i]) +
                           chirp.Value(static_cast<double>(start) * x.dt_s));
      }
    } else {
      level[i] = signals::AprbsSequence(x.samples, {lows[i], highs[i], block, block},
                                        AprbsSeed(x.seed, phase, 10 + i));
    }
  }
  const double dt_s = x.dt_s;
  b.Fill(
      x.samples, dt_s,
      [&](double t, CommandMatrix* c) {
        const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
        c->col(kFlapFrequency).setConstant(level[0][k]);
        c->col(kStrokeAmplitude).setConstant(level[1][k]);
        c->col(kStrokePlaneAngle).setConstant(level[2][k]);
      },
      nullptr, "");
}

void CoupledRoll(const ExcitationContext& x, RunBuilder& b) {
  const Phase phase = x.phase;
  const double a0 = x.a0;
  std::vector<double> u(x.samples);
  if (phase == Phase::kValidate) {
    // A different family from training's: a log chirp plus a multisine, no held levels.
    std::mt19937_64 rng = Stream(x.seed, phase, 20);
    std::vector<double> freqs, amps, phases;
    for (int i = 0; i < 12; ++i) {
      freqs.push_back(0.07 + (2.5 - 0.07) * i / 11.0);
      amps.push_back(1.0);
      phases.push_back(2.0 * kPi * static_cast<double>(rng() >> 11) * 0x1.0p-53);
    }
    const signals::Multisine tones(freqs, amps, phases);
    const signals::LogChirp chirp(0.15, 4.0, 1.0, x.t_end_s, x.phase0);
    double peak = 0.0;
    for (std::size_t k = 0; k < x.samples; ++k)
      peak = std::max(peak, std::abs(tones.Value(static_cast<double>(k) * x.dt_s)));
    const double amplitude_rad = 4.5 * kRadPerDeg;
    for (std::size_t k = 0; k < x.samples; ++k) {
      const double t = static_cast<double>(k) * x.dt_s;
      u[k] = amplitude_rad * (0.5 * chirp.Value(t) + 0.5 * tones.Value(t) / peak);
    }
  } else {
    const bool train = phase == Phase::kTrain;
    const double amplitude_rad = (train ? 6.0 : 5.0) * kRadPerDeg;
    const std::vector<double> levels =
        signals::AprbsSequence(x.samples, {-1.0, 1.0, train ? 15 : 12, train ? 100 : 80, 10},
                               AprbsSeed(x.seed, phase, 20));
    const signals::LinearChirp chirp(train ? 0.1 : 0.12, train ? 3.0 : 3.5, 1.0, x.t_end_s,
                                     x.phase0);
    for (std::size_t k = 0; k < x.samples; ++k) {
      u[k] = amplitude_rad * (0.6 * levels[k] + 0.4 * chirp.Value(static_cast<double>(k) * x.dt_s));
    }
  }
  const double dt_s = x.dt_s;
  b.Fill(
      x.samples, dt_s,
      [&](double t, CommandMatrix* c) {
        const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
        const double uk = x.Fade(t) * u[k];
        for (int i = 0; i < 2; ++i) {
          (*c)(kLeft[i], kStrokeAmplitude) = a0 + uk;
          (*c)(kRight[i], kStrokeAmplitude) = a0 - uk;
        }
      },
      RollChannelRad, "u_roll_rad");
}

void DamageLevels(const ExcitationContext& x, RunBuilder& b) {
  const int hold_min = 30, hold_max = 100;
  const std::vector<double> f = signals::AprbsSequence(x.samples, {5.0, 7.0, hold_min, hold_max},
                                                       AprbsSeed(x.seed, x.phase, 30));
  const std::vector<double> a =
      signals::AprbsSequence(x.samples, {35.0 * kRadPerDeg, 80.0 * kRadPerDeg, hold_min, hold_max},
                             AprbsSeed(x.seed, x.phase, 32));
  const double dt_s = x.dt_s;
  b.Fill(
      x.samples, dt_s,
      [&](double t, CommandMatrix* c) {
        const std::size_t k = static_cast<std::size_t>(std::llround(t / dt_s));
        c->col(kFlapFrequency).setConstant(f[k]);
        c->col(kStrokeAmplitude).setConstant(a[k]);
      },
      nullptr, "");
}

}  // namespace

std::vector<ExperimentPreset> BeyondPaperPresets() {
  std::vector<ExperimentPreset> v;
  {
    ExperimentPreset p = BeyondPaper(
        Attitude("vertical_wide", "vz_mps_avg", "u_vertical_applied_rad", 0.5, "-", 0, kNotInPaper),
        1, 3, 5);
    p.input_columns = {"u_freq_hz", "u_vertical_applied_rad"};
    p.description =
        "beat-averaged vertical velocity over a wide operating range: f and phi0 of all four "
        "wings held at random levels (lift ~ f^2 phi0^2, damping depends on the climb rate)";
    p.train_excitation =
        "all wings: f in 4.6-6.6 Hz and phi0 in 38-84 deg, APRBS levels held 0.3-2 s (one stream "
        "each); 1 s fade from trim; attitude hold on";
    p.select_excitation = "as training, levels held 0.25-1.6 s, other streams";
    p.validate_excitation =
        "a different family: f = 5.6 + 0.95 log-chirp(0.02->0.6 Hz) Hz, phi0 = 61 + 21.9 deg "
        "log-chirp(0.03->1 Hz); 1 s fade from trim; attitude hold on";
    p.excite = [](const ExcitationContext& x, RunBuilder& b) { WideRange(x, b, true); };
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        BeyondPaper(Actuator("force_map_fz", "fz_total_n_avg",
                             {"w1_freq_hz", "w1_amp_rad", "w1_beta_rad"}, 0.5, "-", 0, kNotInPaper),
                    0, 1, 25);
    p.description =
        "static map (f, phi0, beta) -> beat-averaged total vertical force on the test stand: "
        "levels held 0.25 s (longer than a beat), one row per level";
    p.train_excitation =
        "all wings: f in 4.5-7.5 Hz, phi0 in 25-84.9 deg, beta in -25..25 deg, independent "
        "uniform levels, each held 25 samples";
    p.select_excitation = "as training, other streams";
    p.validate_excitation =
        "a different family: levels sampled every 25 samples from slow log-chirps over the same "
        "ranges (f 0.01->0.5 Hz, phi0 0.02->1.2 Hz, beta 0.015->0.8 Hz)";
    p.excite = ForceMapLevels;
    v.push_back(p);
  }
  {
    ExperimentPreset p = BeyondPaper(
        Attitude("roll_coupled", "roll_rad", "u_roll_applied_rad", 0.5, "-", 0, kNotInPaper), 1, 8,
        3);
    p.input_columns = {"u_roll_applied_rad", "vy_mps_avg"};
    p.description =
        "roll with the coupled lateral state: inputs the applied left/right phi0 differential "
        "and the beat-averaged side velocity v_y (open loop, hold included)";
    p.train_excitation =
        "phi0 = trim +/- u (left +, right -), u = 6 deg (0.6 APRBS held 0.15-1 s, smoothed "
        "0.1 s + 0.4 linear chirp(0.1->3 Hz)), 1 s fades; attitude hold on";
    p.select_excitation =
        "as training, u = 5 deg, APRBS held 0.12-0.8 s (other stream), chirp(0.12->3.5 Hz)";
    p.validate_excitation =
        "a different family: u = 4.5 deg (0.5 log-chirp(0.15->4 Hz) + 0.5 multisine of 12 "
        "tones 0.07-2.5 Hz, random phases), 1 s fades; attitude hold on";
    p.excite = CoupledRoll;
    v.push_back(p);
  }
  // The damage scenarios: one stationary excitation family in all three phases (so accuracy
  // before and after the change is comparable), the vehicle changing halfway through the
  // validation run.
  {
    ExperimentPreset p = BeyondPaper(
        Actuator("wing_damage", "fz1_n", {"w1_freq_hz", "w1_amp_rad"}, 0.5, "-", 0, kNotInPaper), 2,
        2, 1);
    p.description =
        "DAMAGE: wing 1's vertical force on the test stand; halfway through the validation run "
        "wing 1 loses 30 % of its stroke amplitude (it still receives the full command)";
    p.select_duration_s = 30.0;
    p.validate_damage.at_s = 30.0;
    p.validate_damage.wing = 1;
    p.validate_damage.amplitude_scale = 0.7;
    p.train_excitation =
        "all wings: f in 5-7 Hz and phi0 in 35-80 deg, APRBS levels held 0.3-1 s (one stream "
        "each)";
    p.select_excitation = "as training, other streams";
    p.validate_excitation = "as training, other streams; from 30 s wing 1 flies 0.7 phi0";
    p.excite = DamageLevels;
    v.push_back(p);
  }
  {
    ExperimentPreset p = *std::find_if(
        v.begin(), v.end(), [](const ExperimentPreset& q) { return q.name == "vertical_wide"; });
    p.name = "battery_sag";
    p.description =
        "DAMAGE: beat-averaged vertical velocity in free flight; halfway through the validation "
        "run every wing's flapping frequency sags to 90 % of the command (a tired battery)";
    p.select_duration_s = 30.0;
    p.validate_damage.at_s = 30.0;
    p.validate_damage.wing = 0;
    p.validate_damage.frequency_scale = 0.9;
    p.train_excitation = "as vertical_wide training (APRBS f and phi0, hold on)";
    p.select_excitation = "as vertical_wide selection";
    p.validate_excitation =
        "as vertical_wide selection, other streams; from 30 s all wings flap at 0.9 f";
    // Stationary: the validation run keeps the training family (APRBS), unlike vertical_wide.
    p.excite = [](const ExcitationContext& x, RunBuilder& b) { WideRange(x, b, false); };
    v.push_back(p);
  }
  return v;
}

}  // namespace odonata::experiments

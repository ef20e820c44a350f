// The paper's test-stand experiments (section IV-A): one wing's wing-beat mean force under
// chirps of flapping frequency and stroke amplitude (and, for F_x, the stroke-plane angle). Each
// preset's table entry and its excitation, together.

#include "experiments/preset_kit.hpp"
#include "plant/angle_constants.hpp"
#include "signals/chirp.hpp"

namespace odonata::experiments {
namespace {

using plant::CommandMatrix;
using plant::kFlapFrequency;
using plant::kRadPerDeg;
using plant::kStrokeAmplitude;
using plant::kStrokePlaneAngle;

// The slow frequency sweep and the faster amplitude sweep of the paper's Fig. 4 and 6; with
// `with_beta`, the stroke-plane angle swept too.
void TestStandSweeps(const ExcitationContext& x, RunBuilder& b, bool with_beta) {
  const double t_end_s = x.t_end_s;
  const Phase phase = x.phase;
  const signals::LinearChirp f_train(0.02, 0.5, 0.5, t_end_s, x.phase0);
  const signals::LinearChirp f_select(0.025, 0.65, 0.75, t_end_s, x.phase0);
  const signals::LogChirp f_val(0.03, 0.8, 1.0, t_end_s, x.phase0);
  const signals::LinearChirp a_train(0.05, 5.0, 30.0 * kRadPerDeg, t_end_s, x.phase1);
  const signals::LinearChirp a_select(0.07, 6.5, 28.0 * kRadPerDeg, t_end_s, x.phase1);
  const signals::LogChirp a_val(0.1, 8.0, 25.0 * kRadPerDeg, t_end_s, x.phase1);
  const signals::LinearChirp beta_train(0.02, 1.0, 10.0 * kRadPerDeg, t_end_s, x.phase2);
  const signals::LinearChirp beta_select(0.025, 1.5, 9.0 * kRadPerDeg, t_end_s, x.phase2);
  const signals::LogChirp beta_val(0.03, 2.0, 8.0 * kRadPerDeg, t_end_s, x.phase2);
  b.Fill(
      x.samples, x.dt_s,
      [&](double t, CommandMatrix* c) {
        const double f = 6.0 + ByPhase(phase, f_train, f_select, f_val, t);
        const double a = 50.0 * kRadPerDeg + ByPhase(phase, a_train, a_select, a_val, t);
        c->col(kFlapFrequency).setConstant(f);
        c->col(kStrokeAmplitude).setConstant(a);
        if (with_beta) {
          c->col(kStrokePlaneAngle)
              .setConstant(ByPhase(phase, beta_train, beta_select, beta_val, t));
        }
      },
      nullptr, "");
}

}  // namespace

std::vector<ExperimentPreset> ActuatorPresets() {
  std::vector<ExperimentPreset> v;
  {
    ExperimentPreset p = Actuator("actuator_fz", "fz1_n", {"w1_freq_hz", "w1_amp_rad"}, 0.007,
                                  "0.178 -> 0.007", 18, "\"highly accurate\"");
    p.description = "wing-beat mean vertical force of one wing on a test stand, varying f and phi0";
    p.train_excitation =
        "all wings: f = 6.0 + 0.5 chirp(0.02->0.5 Hz) Hz (5.5-6.5 Hz); phi0 = 50 deg + 30 deg "
        "linear chirp(0.05->5 Hz)";
    p.validate_excitation =
        "all wings: f = 6.0 + 1.0 log-chirp(0.03->0.8 Hz) Hz (5-7 Hz); phi0 = 50 deg + 25 deg "
        "log-chirp(0.1->8 Hz)";
    p.select_excitation =
        "all wings: f = 6.0 + 0.75 chirp(0.025->0.65 Hz) Hz (5.25-6.75 Hz); phi0 = 50 deg + 28 "
        "deg linear chirp(0.07->6.5 Hz)";
    p.excite = [](const ExcitationContext& x, RunBuilder& b) { TestStandSweeps(x, b, false); };
    v.push_back(p);
  }
  {
    ExperimentPreset p =
        Actuator("actuator_fx", "fx1_n", {"w1_beta_rad", "w1_freq_hz", "w1_amp_rad"}, 0.002,
                 "0.002", 8, "> 80 %");
    p.description =
        "wing-beat mean horizontal force of one wing on a test stand, varying beta, f and phi0";
    p.train_excitation = "as actuator_fz training, plus beta = 10 deg chirp(0.02->1 Hz)";
    p.validate_excitation = "as actuator_fz validation, plus beta = 8 deg log-chirp(0.03->2 Hz)";
    p.select_excitation = "as actuator_fz selection, plus beta = 9 deg chirp(0.025->1.5 Hz)";
    p.excite = [](const ExcitationContext& x, RunBuilder& b) { TestStandSweeps(x, b, true); };
    v.push_back(p);
  }
  return v;
}

}  // namespace odonata::experiments

#include "experiments/experiment_preset.hpp"

#include <cmath>
#include <stdexcept>
#include <utility>

#include "experiments/preset_kit.hpp"

namespace odonata::experiments {

const std::vector<ExperimentPreset>& Presets() {
  static const std::vector<ExperimentPreset> kPresets = [] {
    // The paper's in its order (test stand, free flight, held variants), then beyond it.
    std::vector<ExperimentPreset> v = ActuatorPresets();
    for (auto family : {AttitudePresets, BeyondPaperPresets})
      for (ExperimentPreset& p : family()) v.push_back(std::move(p));
    return v;
  }();
  return kPresets;
}

const ExperimentPreset* FindPreset(const std::string& name) {
  for (const ExperimentPreset& p : Presets()) {
    if (p.name == name) return &p;
  }
  return nullptr;
}

std::string PresetNames() {
  std::string names;
  for (const ExperimentPreset& p : Presets()) names += (names.empty() ? "" : ", ") + p.name;
  return names;
}

const char* PhaseName(Phase phase) {
  switch (phase) {
    case Phase::kTrain:
      return "train";
    case Phase::kSelect:
      return "select";
    case Phase::kValidate:
      break;
  }
  return "validate";
}

std::optional<Phase> ParsePhase(const std::string& name) {
  for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
    if (name == PhaseName(phase)) return phase;
  }
  return std::nullopt;
}

const std::vector<std::string>& PhaseNames() {
  static const std::vector<std::string> kNames = {"train", "select", "validate"};
  return kNames;
}

double PhaseDurationS(const ExperimentPreset& preset, Phase phase) {
  switch (phase) {
    case Phase::kTrain:
      return preset.train_duration_s;
    case Phase::kSelect:
      return preset.select_duration_s;
    case Phase::kValidate:
      break;
  }
  return preset.validate_duration_s;
}

ExperimentRun BuildExperimentRun(const ExperimentPreset& preset, Phase phase, std::uint64_t seed,
                                 double duration_s, const plant::PlantConfig& config) {
  if (!preset.excite)
    throw std::runtime_error("BuildExperimentRun: no excitation defined for preset " + preset.name);
  const plant::TrimResult trim = plant::FindHoverTrim(config);
  const double dt_s = 1.0 / config.integration.sample_rate_hz;
  const double t_end_s = duration_s > 0.0 ? duration_s : PhaseDurationS(preset, phase);
  const std::size_t samples = static_cast<std::size_t>(std::llround(t_end_s / dt_s));

  RunBuilder b{config, trim, {}};
  b.run.trim = trim;
  b.run.sample_period_s = dt_s;
  b.run.initial.prior_command = trim.command;
  b.run.initial.clamped_body = preset.clamped_body;
  b.run.attitude_hold = preset.attitude_hold;
  b.run.record_applied = preset.attitude_hold;
  b.run.hold_gains = vehicle::DefaultAttitudeHoldGains();
  b.run.initial.state.position_m = Eigen::Vector3d(0.0, 0.0, preset.start_altitude_m);
  if (phase == Phase::kValidate) b.run.damage = preset.validate_damage;
  // The preset's own excitation (its family's file; a held variant flies its base preset's).
  const ExcitationContext context{preset,
                                  phase,
                                  seed,
                                  t_end_s,
                                  dt_s,
                                  samples,
                                  trim,
                                  trim.amp_rad,
                                  RandomPhaseRad(seed, phase, 1),
                                  RandomPhaseRad(seed, phase, 2),
                                  RandomPhaseRad(seed, phase, 3)};
  preset.excite(context, b);
  return b.run;
}

}  // namespace odonata::experiments

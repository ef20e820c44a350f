#include "pipeline/vehicle_setup.hpp"

#include <cmath>
#include <stdexcept>

#include "plant/trim_finder.hpp"

namespace odonata::pipeline {

VehicleSetup PresetVehicleSetup(const experiments::ExperimentPreset& preset,
                                const plant::PlantConfig& config, experiments::Phase phase) {
  // Building the (cheap) run is the one way to get exactly the initial condition and damage the
  // preset's offline runs fly; the seed only changes the commands.
  const experiments::ExperimentRun run =
      experiments::BuildExperimentRun(preset, phase, 1, 0.0, config);
  VehicleSetup setup;
  setup.name = preset.name;
  setup.initial = run.initial;
  setup.attitude_hold = run.attitude_hold;
  setup.hold_gains = run.hold_gains;
  setup.trim_command = run.trim.command;
  setup.damage = run.damage;
  return setup;
}

std::string SetupName(const experiments::ExperimentPreset& preset, experiments::Phase phase) {
  const bool changes =
      phase == experiments::Phase::kValidate && std::isfinite(preset.validate_damage.at_s);
  return changes ? preset.name + "@" + experiments::PhaseName(phase) : preset.name;
}

VehicleSetup DefaultVehicleSetup(const plant::PlantConfig& config) {
  const plant::TrimResult trim = plant::FindHoverTrim(config);
  VehicleSetup setup;
  setup.name = "default";
  setup.initial.state.position_m = Eigen::Vector3d(0.0, 0.0, kDefaultStartAltitudeM);
  setup.initial.prior_command = trim.command;
  setup.trim_command = trim.command;
  return setup;
}

VehicleSetup VehicleSetupByName(const std::string& name, const plant::PlantConfig& config) {
  if (name.empty() || name == "default") return DefaultVehicleSetup(config);
  const std::size_t at = name.find('@');
  const std::string preset_name = name.substr(0, at);
  const experiments::ExperimentPreset* preset = experiments::FindPreset(preset_name);
  if (!preset) {
    throw std::invalid_argument("unknown preset '" + preset_name +
                                "'; known presets: " + experiments::PresetNames());
  }
  experiments::Phase phase = experiments::Phase::kTrain;
  if (at != std::string::npos) {
    const auto parsed = experiments::ParsePhase(name.substr(at + 1));
    if (!parsed) {
      throw std::invalid_argument("unknown phase in set-up '" + name +
                                  "'; known phases: train, select, validate");
    }
    phase = *parsed;
  }
  return PresetVehicleSetup(*preset, config, phase);
}

}  // namespace odonata::pipeline

#include "pipeline/vehicle_setup.hpp"

#include <stdexcept>

#include "plant/trim_finder.hpp"

namespace odonata::pipeline {

VehicleSetup PresetVehicleSetup(const experiments::ExperimentPreset& preset,
                                const plant::PlantConfig& config) {
  // Building the (cheap) default run is the one way to get exactly the initial condition the
  // preset's offline runs start from; phase and seed only change the commands.
  const experiments::ExperimentRun run =
      experiments::BuildExperimentRun(preset, experiments::Phase::kTrain, 1, 0.0, config);
  VehicleSetup setup;
  setup.name = preset.name;
  setup.initial = run.initial;
  setup.attitude_hold = run.attitude_hold;
  setup.hold_gains = run.hold_gains;
  setup.trim_command = run.trim.command;
  return setup;
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
  const experiments::ExperimentPreset* preset = experiments::FindPreset(name);
  if (!preset) {
    throw std::invalid_argument("unknown preset '" + name +
                                "'; known presets: " + experiments::PresetNames());
  }
  return PresetVehicleSetup(*preset, config);
}

}  // namespace odonata::pipeline

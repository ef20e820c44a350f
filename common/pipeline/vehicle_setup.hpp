#pragma once
// How the simulated vehicle starts and flies: what an experiment preset (or the default) asks of
// the plant itself, as opposed to the commands sent to it.

#include <string>

#include "experiments/attitude_hold.hpp"
#include "experiments/experiment_preset.hpp"
#include "plant/dimav_plant.hpp"
#include "plant/plant_config.hpp"

namespace odonata::pipeline {

/// Initial condition, onboard stabiliser and hover trim of one run.
struct VehicleSetup {
  std::string name;                   ///< the preset's name, or "default"
  plant::InitialCondition initial{};  ///< state at t = 0
  bool attitude_hold{};               ///< the vehicle's onboard roll/pitch hold is on
  experiments::AttitudeHoldGains hold_gains{};
  plant::CommandMatrix trim_command{plant::CommandMatrix::Zero()};  ///< hover trim
};

/// Start altitude of the default set-up (m), odonata-sim's default for command files.
inline constexpr double kDefaultStartAltitudeM = 50.0;

/// The set-up BuildExperimentRun() gives `preset` (it is taken from there, so the two cannot
/// drift apart): the clamped test stand for the actuator presets, free flight at altitude with
/// the attitude hold for the others. Independent of phase, seed and duration.
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
VehicleSetup PresetVehicleSetup(const experiments::ExperimentPreset& preset,
                                const plant::PlantConfig& config);

/// Free flight at rest at kDefaultStartAltitudeM, wings flapping at hover trim, no hold: the
/// vehicle odonata-sim flies for a command file (which primes the wings with the file's first
/// command instead of the trim).
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
VehicleSetup DefaultVehicleSetup(const plant::PlantConfig& config);

/// PresetVehicleSetup() of the preset called `name`, or DefaultVehicleSetup() for "" or
/// "default". @throws std::invalid_argument for an unknown name, listing the known ones.
VehicleSetup VehicleSetupByName(const std::string& name, const plant::PlantConfig& config);

}  // namespace odonata::pipeline

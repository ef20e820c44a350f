#pragma once
// How the simulated vehicle starts and flies: what an experiment preset (or the default) asks of
// the plant itself, as opposed to the commands sent to it.

#include <string>

#include "experiments/experiment_preset.hpp"
#include "plant/dimav_plant.hpp"
#include "plant/plant_config.hpp"
#include "vehicle/attitude_hold.hpp"

namespace odonata::pipeline {

/// Initial condition, onboard stabiliser and hover trim of one run.
struct VehicleSetup {
  std::string name;                   ///< the preset's name, or "default"
  plant::InitialCondition initial{};  ///< state at t = 0
  bool attitude_hold{};               ///< the vehicle's onboard roll/pitch hold is on
  vehicle::AttitudeHoldGains hold_gains{};
  plant::CommandMatrix trim_command{plant::CommandMatrix::Zero()};  ///< hover trim
  /// What fails during the run (a damage preset's validation run); nothing by default.
  plant::ActuatorDamage damage{};
};

/// Start altitude of the default set-up (m), odonata-sim's default for command files.
inline constexpr double kDefaultStartAltitudeM = 50.0;

/// The set-up BuildExperimentRun() gives `preset` (it is taken from there, so the two cannot
/// drift apart): the clamped test stand for the actuator presets, free flight at altitude with
/// the attitude hold for the others. Independent of seed and duration; the phase only matters to
/// the damage presets, whose validation run damages the vehicle halfway.
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
VehicleSetup PresetVehicleSetup(const experiments::ExperimentPreset& preset,
                                const plant::PlantConfig& config,
                                experiments::Phase phase = experiments::Phase::kTrain);

/// The set-up name that asks the plant for `preset` in `phase` (a control_t RESET's path):
/// "wing_damage@validate" where the phase changes the vehicle, the bare preset name otherwise.
std::string SetupName(const experiments::ExperimentPreset& preset, experiments::Phase phase);

/// Free flight at rest at kDefaultStartAltitudeM, wings flapping at hover trim, no hold: the
/// vehicle odonata-sim flies for a command file (which primes the wings with the file's first
/// command instead of the trim).
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
VehicleSetup DefaultVehicleSetup(const plant::PlantConfig& config);

/// PresetVehicleSetup() of the preset called `name` (optionally "preset@phase", see SetupName()),
/// or DefaultVehicleSetup() for "" or "default".
/// @throws std::invalid_argument for an unknown name or phase, listing the known ones.
VehicleSetup VehicleSetupByName(const std::string& name, const plant::PlantConfig& config);

}  // namespace odonata::pipeline

#pragma once
// One sample of the vehicle as it flies a command: the onboard attitude hold acts on the output
// before the step, the result is clamped to the actuator limits, and a damaged wing flies less
// than it is told. odonata-sim and the plant service (pipeline/plant_session.hpp) both step
// through here, so a CSV row and a bus sample mean the same thing.

#include "plant/actuator_damage.hpp"
#include "plant/dimav_plant.hpp"
#include "vehicle/attitude_hold.hpp"

namespace odonata::vehicle {

struct VehicleStep {
  /// What the vehicle's own command path applied over the sample (hold added, clamped), before
  /// any damage: what odonata-sim writes and the plant reports as applied.
  plant::CommandMatrix applied;
  plant::StepStatus status = plant::StepStatus::kOk;
};

/// Steps `plant` one sample from t_s under `command`. The clamp only ever bites on the hold's
/// correction when the command itself is in limits.
VehicleStep StepVehicle(plant::DimavPlant& plant, const plant::CommandMatrix& command,
                        bool attitude_hold, const AttitudeHoldGains& hold_gains,
                        const plant::ActuatorDamage& damage, double t_s);

}  // namespace odonata::vehicle

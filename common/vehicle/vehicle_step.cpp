#include "vehicle/vehicle_step.hpp"

namespace odonata::vehicle {

VehicleStep StepVehicle(plant::DimavPlant& plant, const plant::CommandMatrix& command,
                        bool attitude_hold, const AttitudeHoldGains& hold_gains,
                        const plant::ActuatorDamage& damage, double t_s) {
  VehicleStep step;
  step.applied = plant.ClampToLimits(
      attitude_hold ? ApplyAttitudeHold(hold_gains, command, plant.output()) : command);
  step.status = plant.Step(damage.Apply(step.applied, t_s));
  return step;
}

}  // namespace odonata::vehicle

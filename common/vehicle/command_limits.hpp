#pragma once
// Checks a received command against the actuator limits before it reaches the plant.

#include <string>

#include "plant/plant_config.hpp"
#include "plant/wing_command.hpp"

namespace odonata::vehicle {

/// Every problem of `command`, one per line ("w2_amp_rad = 1.6 is above its limit 1.48"), or an
/// empty string when every entry is finite and inside its inclusive limit.
std::string CommandLimitProblems(const plant::CommandMatrix& command,
                                 const plant::ActuatorLimits& limits);

}  // namespace odonata::vehicle

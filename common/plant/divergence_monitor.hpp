#pragma once
// Decides whether the simulated state has diverged (non-finite, tumbling, runaway).

#include <string>

#include "plant/plant_config.hpp"
#include "plant/rigid_body.hpp"

namespace odonata::plant {

/// Returns an empty string if the state is acceptable, otherwise one sentence saying which limit
/// was exceeded and by how much (e.g. "|roll| 1.52 rad exceeds max_tilt_rad 1.40").
std::string CheckDivergence(const DivergenceSettings& limits, const RigidBodyState& state);

}  // namespace odonata::plant

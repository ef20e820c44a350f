#pragma once
// Flat ground: the centre of mass never goes below the ground height.

#include "plant/plant_config.hpp"
#include "plant/rigid_body.hpp"

namespace odonata::plant {

/// Projects the state onto the admissible set after an integration step. Contact is inelastic and
/// sticking: if the centre of mass is at or below the ground and moving down, its height is set to
/// the ground and its velocity and angular rate to zero (attitude is kept). A vehicle producing
/// more than its weight in lift simply leaves again on the next step.
/// @return true if the vehicle is in contact with the ground after the projection.
bool ApplyGroundContact(const GroundSettings& ground, RigidBodyState* state);

}  // namespace odonata::plant

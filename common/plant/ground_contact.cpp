#include "plant/ground_contact.hpp"

namespace odonata::plant {

bool ApplyGroundContact(const GroundSettings& ground, RigidBodyState* state) {
  if (!ground.enabled || state->position_m.z() > ground.height_m) return false;
  state->position_m.z() = ground.height_m;
  const Eigen::Vector3d velocity_world_mps = state->attitude * state->velocity_body_mps;
  if (velocity_world_mps.z() <= 0.0) {
    state->velocity_body_mps.setZero();
    state->rate_body_radps.setZero();
  }
  return true;
}

}  // namespace odonata::plant

#include "plant/divergence_monitor.hpp"

#include <cmath>
#include <cstdio>

namespace odonata::plant {
namespace {
std::string Exceeds(const char* what, double value, const char* limit_name, double limit) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "%s %.3g exceeds %s %.3g", what, value, limit_name, limit);
  return buf;
}
}  // namespace

std::string CheckDivergence(const DivergenceSettings& limits, const RigidBodyState& state) {
  const bool finite = state.position_m.allFinite() && state.attitude.coeffs().allFinite() &&
                      state.velocity_body_mps.allFinite() && state.rate_body_radps.allFinite();
  if (!finite) return "the state is not finite (NaN or Inf)";
  const Eigen::Vector3d rpy = RollPitchYaw(state.attitude);
  if (std::fabs(rpy.x()) > limits.max_tilt_rad) {
    return Exceeds("|roll| (rad)", std::fabs(rpy.x()), "max_tilt_rad", limits.max_tilt_rad);
  }
  if (std::fabs(rpy.y()) > limits.max_tilt_rad) {
    return Exceeds("|pitch| (rad)", std::fabs(rpy.y()), "max_tilt_rad", limits.max_tilt_rad);
  }
  const double rate = state.rate_body_radps.norm();
  if (rate > limits.max_rate_radps) {
    return Exceeds("|omega_b| (rad/s)", rate, "max_rate_radps", limits.max_rate_radps);
  }
  const double speed = state.velocity_body_mps.norm();
  if (speed > limits.max_speed_mps) {
    return Exceeds("|V_b| (m/s)", speed, "max_speed_mps", limits.max_speed_mps);
  }
  return {};
}

}  // namespace odonata::plant

#include "plant/wing_kinematics.hpp"

#include <cmath>

#include "plant/angle_constants.hpp"

namespace odonata::plant {
WingAngles EvaluateWingAngles(double phase_rad, double freq_hz, double amp_rad,
                              double pitch_mean_rad, double pitch_amp_rad, double pitch_phase_rad) {
  const double omega_radps = kTwoPi * freq_hz;
  const double pitch_arg_rad = phase_rad + pitch_phase_rad;
  WingAngles a;
  a.stroke_rad = amp_rad * std::cos(phase_rad);
  a.stroke_rate_radps = -amp_rad * omega_radps * std::sin(phase_rad);
  a.pitch_rad = pitch_mean_rad - pitch_amp_rad * std::sin(pitch_arg_rad);
  a.pitch_rate_radps = -pitch_amp_rad * omega_radps * std::cos(pitch_arg_rad);
  return a;
}

WingFrame ComputeWingFrame(double stroke_plane_rad, double stroke_rad, double pitch_rad,
                           double side_sign) {
  const double sb = std::sin(stroke_plane_rad);
  const double cb = std::cos(stroke_plane_rad);
  const double sp = std::sin(stroke_rad);
  const double cp = std::cos(stroke_rad);
  const double st = std::sin(pitch_rad);
  const double ct = std::cos(pitch_rad);
  const Eigen::Vector3d normal(sb, 0.0, cb);
  const Eigen::Vector3d down(cb, 0.0, -sb);
  const Eigen::Vector3d root_span(0.0, side_sign, 0.0);
  const Eigen::Vector3d local_down = sp * root_span + cp * down;
  WingFrame f;
  f.span = cp * root_span - sp * down;
  f.chord = ct * local_down + st * normal;
  f.chord_normal = -st * local_down + ct * normal;
  return f;
}

}  // namespace odonata::plant

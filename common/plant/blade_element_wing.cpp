#include "plant/blade_element_wing.hpp"

#include <cmath>

#include "plant/wing_kinematics.hpp"

namespace odonata::plant {

BladeElementWing::BladeElementWing(const WingGeometry& geometry, double air_density_kgpm3,
                                   bool rotational_forces, const Eigen::Vector3d& hinge_position_m,
                                   double side_sign)
    : hinge_position_m_(hinge_position_m), side_sign_(side_sign) {
  const int n = geometry.strip_count;
  const double dr_m = geometry.length_m / n;
  strip_span_m_.resize(n);
  for (int i = 0; i < n; ++i) strip_span_m_[i] = geometry.root_offset_m + (i + 0.5) * dr_m;
  dynamic_factor_ = 0.5 * air_density_kgpm3 * geometry.chord_m * dr_m;
  rotational_factor_ = rotational_forces
                           ? RotationalForceCoefficient(geometry.pitch_axis_chords) *
                                 air_density_kgpm3 * geometry.chord_m * geometry.chord_m * dr_m
                           : 0.0;
}

WingLoad BladeElementWing::Compute(const Eigen::Matrix<double, 1, kCommandsPerWing>& command,
                                   double phase_rad, const Eigen::Vector3d& velocity_body_mps,
                                   const Eigen::Vector3d& rate_body_radps) const {
  const WingAngles a =
      EvaluateWingAngles(phase_rad, command(kFlapFrequency), command(kStrokeAmplitude),
                         command(kPitchMean), command(kPitchAmplitude), command(kPitchPhase));
  const WingFrame f =
      ComputeWingFrame(command(kStrokePlaneAngle), a.stroke_rad, a.pitch_rad, side_sign_);

  // v(r) = v_hinge + r (φ̇ t̂ + ω × ŝ), with t̂ = −d̂ₗ so that ĉ·t̂ = −cos θ and ĉ⊥·t̂ = sin θ.
  const Eigen::Vector3d v_hinge = velocity_body_mps + rate_body_radps.cross(hinge_position_m_);
  const Eigen::Vector3d w_span = rate_body_radps.cross(f.span);
  const double ct = std::cos(a.pitch_rad);
  const double st = std::sin(a.pitch_rad);
  const double a_c = f.chord.dot(v_hinge);
  const double a_n = f.chord_normal.dot(v_hinge);
  const double b_c = -a.stroke_rate_radps * ct + f.chord.dot(w_span);
  const double b_n = a.stroke_rate_radps * st + f.chord_normal.dot(w_span);
  const double rot_gain = rotational_factor_ * a.pitch_rate_radps;

  // Sums in chord coordinates: Σ F and Σ r F (for the moment of the span offsets).
  double f_c = 0.0, f_n = 0.0, rf_c = 0.0, rf_n = 0.0;
  for (const double r : strip_span_m_) {
    const double vc = a_c + r * b_c;
    const double vn = a_n + r * b_n;
    const double avc = std::fabs(vc);
    const double avn = std::fabs(vn);
    const double sum = avc + avn;
    if (sum <= 1e-12) continue;  // no relative velocity, no load
    const double speed = std::sqrt(vc * vc + vn * vn);
    double cl, cd;
    table_.Evaluate(avn / sum, &cl, &cd);
    const double q = dynamic_factor_ * speed;  // ½ρ c dr |v|
    // Lift ∝ (sgn(v_c)|v_n|, −sgn(v_n)|v_c|): ⊥ v, on the side of the leading chord ĉ' = sgn(v_c)ĉ.
    const double sgn_c = vc > 0.0 ? 1.0 : (vc < 0.0 ? -1.0 : 0.0);
    const double sgn_n = vn > 0.0 ? 1.0 : (vn < 0.0 ? -1.0 : 0.0);
    const double dfc = q * (-cd * vc + cl * sgn_c * avn);
    const double dfn = q * (-cd * vn - cl * sgn_n * avc) + rot_gain * speed * sgn_c;
    f_c += dfc;
    f_n += dfn;
    rf_c += r * dfc;
    rf_n += r * dfn;
  }
  WingLoad load;
  load.force_n = f_c * f.chord + f_n * f.chord_normal;
  load.moment_nm =
      hinge_position_m_.cross(load.force_n) + f.span.cross(rf_c * f.chord + rf_n * f.chord_normal);
  return load;
}

}  // namespace odonata::plant

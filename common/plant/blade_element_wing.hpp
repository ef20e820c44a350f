#pragma once
// Quasi-steady blade-element forces of one flapping wing (translational lift and drag plus the
// rotational-circulation force), summed into a force and a moment about the centre of mass.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <vector>

#include "plant/aero_coefficients.hpp"
#include "plant/plant_config.hpp"

namespace odonata::plant {

/// Force and moment of one wing in the body frame.
struct WingLoad {
  Eigen::Vector3d force_n{Eigen::Vector3d::Zero()};
  Eigen::Vector3d moment_nm{Eigen::Vector3d::Zero()};  ///< about the centre of mass (body origin)
};

/// One wing: geometry and strips are precomputed at construction so Compute() allocates nothing.
///
/// Each strip at span r (midpoint rule) sees the velocity v = r φ̇ t̂ + ω_b × (h + r ŝ) + V_b
/// (t̂ = ∂ŝ/∂φ; keeping ω_b and V_b gives the aerodynamic damping). Only the part of v in the
/// chord-normal plane (⊥ span) loads the strip (independence principle). With v_c = ĉ·v,
/// v_n = ĉ⊥·v, |v|² = v_c² + v_n², α = atan2(|v_n|, |v_c|) ∈ [0, π/2]:
///   drag  dD = ½ρ|v|² C_D(α) c dr along −v̂,
///   lift  dL = ½ρ|v|² C_L(α) c dr ⊥ v̂ in the chord-normal plane, on the side of the chord that
///         leads (so a wing moving with its leading edge up at 0 < α < 90° lifts up),
///   rotational dF = C_rot ρ c² |v| θ̇ dr along ±ĉ⊥, the direction the leading chord turns
///         (pitch-up about the moving leading edge adds to the normal force).
/// Because v is affine in r and the wing frame is shared by all strips, the loop works on two
/// scalars per strip and forms the 3-D force and moment once per wing.
class BladeElementWing {
 public:
  /// @param hinge_position_m hinge in the body frame; @param side_sign +1 left wing, −1 right.
  /// @pre geometry.strip_count ≥ 1, geometry lengths > 0, air_density_kgpm3 > 0.
  BladeElementWing(const WingGeometry& geometry, double air_density_kgpm3, bool rotational_forces,
                   const Eigen::Vector3d& hinge_position_m, double side_sign);

  /// Load at one instant.
  /// @param command this wing's six inputs (CommandIndex order; f and φ₀ as commanded).
  /// @param phase_rad integrated stroke phase Φ of this wing (rad).
  /// @param velocity_body_mps V_b, @param rate_body_radps ω_b (body frame).
  WingLoad Compute(const Eigen::Matrix<double, 1, kCommandsPerWing>& command, double phase_rad,
                   const Eigen::Vector3d& velocity_body_mps,
                   const Eigen::Vector3d& rate_body_radps) const;

  const Eigen::Vector3d& hinge_position_m() const { return hinge_position_m_; }
  double side_sign() const { return side_sign_; }
  int strip_count() const { return static_cast<int>(strip_span_m_.size()); }

 private:
  std::vector<double> strip_span_m_;  // r_i, stroke axis (hinge) to strip midpoint
  double dynamic_factor_{};           // ½ ρ c dr (N per (m/s)² per unit coefficient)
  double rotational_factor_{};        // C_rot ρ c² dr, or 0 without rotational forces
  Eigen::Vector3d hinge_position_m_{};
  double side_sign_{};
  AeroCoefficientTable table_;
};

}  // namespace odonata::plant

#pragma once
// 6-DOF rigid body (paper eq. 5–6, with eq. 5's typo fixed): body-frame velocity and rate,
// quaternion attitude, world-frame position; gravity acts along world −z.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace odonata::plant {

/// Size of the packed state vector.
inline constexpr int kRigidBodyStateSize = 13;
/// Packed state: [p_w (3, m), q (w, x, y, z; body → world), V_b (3, m/s), ω_b (3, rad/s)].
using RigidBodyVector = Eigen::Matrix<double, kRigidBodyStateSize, 1>;

/// Readable view of the rigid-body state. Frames: body FLU (x forward, y left, z up), world z up.
struct RigidBodyState {
  Eigen::Vector3d position_m{Eigen::Vector3d::Zero()};          ///< world frame
  Eigen::Quaterniond attitude{Eigen::Quaterniond::Identity()};  ///< rotates body → world
  Eigen::Vector3d velocity_body_mps{Eigen::Vector3d::Zero()};   ///< V_b
  Eigen::Vector3d rate_body_radps{Eigen::Vector3d::Zero()};     ///< ω_b

  RigidBodyVector Pack() const;
  static RigidBodyState Unpack(const RigidBodyVector& x);
};

/// Mass properties: mass and the inertia tensor about the centre of mass in body axes.
class RigidBody {
 public:
  /// @pre mass_kg > 0; inertia_kgm2 symmetric positive definite; gravity_mps2 ≥ 0.
  RigidBody(double mass_kg, const Eigen::Matrix3d& inertia_kgm2, double gravity_mps2);

  /// Time derivative of the packed state under body-frame force F_b and moment M_b:
  ///   ṗ_w = R V_b,  q̇ = ½ q ⊗ (0, ω_b),
  ///   V̇_b = F_b / m + Rᵀ g_w − ω_b × V_b      (F = m(V̇_b + ω × V_b) − m Rᵀ g_w),
  ///   ω̇_b = I⁻¹ (M_b − ω_b × I ω_b).
  /// The quaternion in `x` need not be exactly unit (RK4 stages are not); R uses it normalised.
  RigidBodyVector Derivative(const RigidBodyVector& x, const Eigen::Vector3d& force_body_n,
                             const Eigen::Vector3d& moment_body_nm) const;

  double mass_kg() const { return mass_kg_; }
  const Eigen::Matrix3d& inertia_kgm2() const { return inertia_kgm2_; }

 private:
  double mass_kg_{};
  double gravity_mps2_{};
  Eigen::Matrix3d inertia_kgm2_{};
  Eigen::Matrix3d inverse_inertia_{};
};

/// Roll, pitch, yaw (rad): intrinsic Z-Y-X angles of the body FLU frame in the z-up world frame
/// (REP-103): roll about x (right wing down > 0), pitch about y (nose DOWN > 0, as y points left),
/// yaw about z (nose left > 0). Pitch is in [−π/2, π/2], roll and yaw in (−π, π].
Eigen::Vector3d RollPitchYaw(const Eigen::Quaterniond& attitude);

/// Quaternion (body → world) from Z-Y-X roll, pitch, yaw (rad).
Eigen::Quaterniond QuaternionFromRollPitchYaw(double roll_rad, double pitch_rad, double yaw_rad);

}  // namespace odonata::plant

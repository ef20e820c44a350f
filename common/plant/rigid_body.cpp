#include "plant/rigid_body.hpp"

#include <algorithm>
#include <cmath>

namespace odonata::plant {

RigidBodyVector RigidBodyState::Pack() const {
  RigidBodyVector x;
  x.segment<3>(0) = position_m;
  x(3) = attitude.w();
  x(4) = attitude.x();
  x(5) = attitude.y();
  x(6) = attitude.z();
  x.segment<3>(7) = velocity_body_mps;
  x.segment<3>(10) = rate_body_radps;
  return x;
}

RigidBodyState RigidBodyState::Unpack(const RigidBodyVector& x) {
  RigidBodyState s;
  s.position_m = x.segment<3>(0);
  s.attitude = Eigen::Quaterniond(x(3), x(4), x(5), x(6));
  s.velocity_body_mps = x.segment<3>(7);
  s.rate_body_radps = x.segment<3>(10);
  return s;
}

RigidBody::RigidBody(double mass_kg, const Eigen::Matrix3d& inertia_kgm2, double gravity_mps2)
    : mass_kg_(mass_kg),
      gravity_mps2_(gravity_mps2),
      inertia_kgm2_(inertia_kgm2),
      inverse_inertia_(inertia_kgm2.inverse()) {}

RigidBodyVector RigidBody::Derivative(const RigidBodyVector& x, const Eigen::Vector3d& force_body_n,
                                      const Eigen::Vector3d& moment_body_nm) const {
  const Eigen::Quaterniond q(x(3), x(4), x(5), x(6));
  const Eigen::Matrix3d r = q.normalized().toRotationMatrix();
  const Eigen::Vector3d v = x.segment<3>(7);
  const Eigen::Vector3d w = x.segment<3>(10);
  const Eigen::Vector3d gravity_world(0.0, 0.0, -gravity_mps2_);

  RigidBodyVector dx;
  dx.segment<3>(0) = r * v;
  // q̇ = ½ q ⊗ (0, ω), written out for (w, x, y, z).
  dx(3) = -0.5 * (x(4) * w.x() + x(5) * w.y() + x(6) * w.z());
  dx(4) = 0.5 * (x(3) * w.x() + x(5) * w.z() - x(6) * w.y());
  dx(5) = 0.5 * (x(3) * w.y() + x(6) * w.x() - x(4) * w.z());
  dx(6) = 0.5 * (x(3) * w.z() + x(4) * w.y() - x(5) * w.x());
  dx.segment<3>(7) = force_body_n / mass_kg_ + r.transpose() * gravity_world - w.cross(v);
  dx.segment<3>(10) = inverse_inertia_ * (moment_body_nm - w.cross(inertia_kgm2_ * w));
  return dx;
}

Eigen::Vector3d RollPitchYaw(const Eigen::Quaterniond& attitude) {
  const Eigen::Quaterniond q = attitude.normalized();
  const double roll = std::atan2(2.0 * (q.w() * q.x() + q.y() * q.z()),
                                 1.0 - 2.0 * (q.x() * q.x() + q.y() * q.y()));
  const double sin_pitch = std::clamp(2.0 * (q.w() * q.y() - q.z() * q.x()), -1.0, 1.0);
  const double pitch = std::asin(sin_pitch);
  const double yaw = std::atan2(2.0 * (q.w() * q.z() + q.x() * q.y()),
                                1.0 - 2.0 * (q.y() * q.y() + q.z() * q.z()));
  return Eigen::Vector3d(roll, pitch, yaw);
}

Eigen::Quaterniond QuaternionFromRollPitchYaw(double roll_rad, double pitch_rad, double yaw_rad) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(yaw_rad, Eigen::Vector3d::UnitZ()) *
                            Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
                            Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()));
}

}  // namespace odonata::plant

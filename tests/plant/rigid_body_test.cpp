#include "plant/rigid_body.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "plant/rk4.hpp"

namespace odonata::plant {
namespace {

RigidBody TumblingBody() {
  return RigidBody(0.04, Eigen::Vector3d(1.1e-4, 8e-5, 1.9e-4).asDiagonal().toDenseMatrix(), 0.0);
}

RigidBodyVector Integrate(const RigidBody& body, RigidBodyVector x, double h_s, double t_end_s) {
  const auto f = [&](double, const RigidBodyVector& s, double) {
    return body.Derivative(s, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  };
  const int n = static_cast<int>(std::lround(t_end_s / h_s));
  for (int k = 0; k < n; ++k) x = Rk4Step<kRigidBodyStateSize>(f, x, h_s);
  return x;
}

RigidBodyVector SpinningStart() {
  RigidBodyState s;
  s.rate_body_radps = Eigen::Vector3d(3.0, 0.4, 5.0);  // near the unstable middle axis mix
  s.velocity_body_mps = Eigen::Vector3d(0.5, -0.2, 0.1);
  return s.Pack();
}

// Torque-free: world-frame angular momentum R I ω and kinetic energy are invariants.
TEST(RigidBody, TorqueFreeSpinningBodyKeepsAngularMomentum) {
  const RigidBody body = TumblingBody();
  const RigidBodyState s0 = RigidBodyState::Unpack(SpinningStart());
  const RigidBodyState s1 = RigidBodyState::Unpack(Integrate(body, SpinningStart(), 1e-3, 2.0));
  const Eigen::Matrix3d& i = body.inertia_kgm2();
  const Eigen::Vector3d h0 = s0.attitude.normalized() * (i * s0.rate_body_radps);
  const Eigen::Vector3d h1 = s1.attitude.normalized() * (i * s1.rate_body_radps);
  EXPECT_LT((h1 - h0).norm() / h0.norm(), 1e-8);
  const double e0 = s0.rate_body_radps.dot(i * s0.rate_body_radps);
  const double e1 = s1.rate_body_radps.dot(i * s1.rate_body_radps);
  EXPECT_NEAR(e1 / e0, 1.0, 1e-8);
  // The body really tumbled (the rate vector moved in the body frame).
  EXPECT_GT((s1.rate_body_radps - s0.rate_body_radps).norm(), 0.1);
}

// Halving h divides the global error of RK4 by 2⁴ = 16 (reference: h/16).
TEST(RigidBody, Rk4ConvergesAtFourthOrder) {
  const RigidBody body = TumblingBody();
  const RigidBodyVector ref = Integrate(body, SpinningStart(), 0.02 / 16, 2.0);
  const double e1 = (Integrate(body, SpinningStart(), 0.02, 2.0) - ref).norm();
  const double e2 = (Integrate(body, SpinningStart(), 0.01, 2.0) - ref).norm();
  const double e3 = (Integrate(body, SpinningStart(), 0.005, 2.0) - ref).norm();
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.3);
  EXPECT_NEAR(std::log2(e2 / e3), 4.0, 0.3);
}

TEST(RigidBody, FreeFallAcceleratesAtG) {
  const RigidBody body(0.04, Eigen::Matrix3d::Identity() * 1e-4, 9.81);
  const RigidBodyVector dx =
      body.Derivative(RigidBodyState{}.Pack(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  EXPECT_DOUBLE_EQ(dx(9), -9.81);
}

TEST(RigidBody, RollPitchYawRoundTrip) {
  const Eigen::Vector3d rpy(0.3, -0.2, 2.9);
  EXPECT_LT((RollPitchYaw(QuaternionFromRollPitchYaw(rpy.x(), rpy.y(), rpy.z())) - rpy).norm(),
            1e-12);
}

}  // namespace
}  // namespace odonata::plant

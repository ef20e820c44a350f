#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "sysid/model/arx_model.hpp"
#include "sysid/model/quadratic_arx_model.hpp"

namespace odonata::sysid {
namespace {

TEST(ArxModel, RecoversALinearSystemExactly) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0, 1);
  Series s;
  s.inputs.resize(500, 1);
  s.outputs = Eigen::MatrixXd::Zero(500, 1);
  for (int t = 0; t < 500; ++t) s.inputs(t, 0) = n(rng);
  for (int t = 2; t < 500; ++t)
    s.outputs(t, 0) =
        0.2 + 1.5 * s.outputs(t - 1, 0) - 0.7 * s.outputs(t - 2, 0) + 0.5 * s.inputs(t - 1, 0);
  RegressorSpec spec{2, 1, 1, {"y"}, {"u"}};
  const ArxModel m = ArxModel::Fit(spec, s);
  Eigen::VectorXd expect(4);
  expect << 0.2, 1.5, -0.7, 0.5;
  EXPECT_LT((m.coefficients().col(0) - expect).norm(), 1e-6);
}

}  // namespace
}  // namespace odonata::sysid

namespace odonata::sysid {
namespace {

// y(t) = 0.3 + 0.5 y(t−1) + 2 u₁(t−1)² − u₁(t−1) u₂(t−1) + 0.4 u₂(t−2): quadratic in the inputs.
Series QuadraticSystem(int samples, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Series s;
  s.inputs.resize(samples, 2);
  s.outputs = Eigen::MatrixXd::Zero(samples, 1);
  for (int t = 0; t < samples; ++t) s.inputs.row(t) << u(rng), 5.0 + u(rng);
  for (int t = 2; t < samples; ++t) {
    const double u1 = s.inputs(t - 1, 0), u2 = s.inputs(t - 1, 1);
    s.outputs(t, 0) =
        0.3 + 0.5 * s.outputs(t - 1, 0) + 2.0 * u1 * u1 - u1 * u2 + 0.4 * s.inputs(t - 2, 1);
  }
  return s;
}

TEST(QuadraticArxModel, RecoversASystemQuadraticInItsInputsWhereArxCannot) {
  const RegressorSpec spec{1, 2, 1, {"y"}, {"u1", "u2"}};
  const Series train = QuadraticSystem(600, 4), test = QuadraticSystem(300, 5);
  const QuadraticArxModel q = QuadraticArxModel::Fit(spec, train);
  // 1 output lag + 2 inputs × 2 lags, plus 3 products per lag.
  EXPECT_EQ(q.features(), 5 + 6);
  const ArxModel a = ArxModel::Fit(spec, train);
  const RegressionData d = BuildRegression(spec, test);
  double q_error = 0.0, a_error = 0.0;
  for (Eigen::Index r = 0; r < d.x.rows(); ++r) {
    const Eigen::VectorXd x = d.x.row(r).transpose();
    q_error = std::max(q_error, std::abs(q.Predict(x)(0) - d.y(r, 0)));
    a_error = std::max(a_error, std::abs(a.Predict(x)(0) - d.y(r, 0)));
  }
  EXPECT_LT(q_error, 1e-6);
  EXPECT_GT(a_error, 0.1);
}

}  // namespace
}  // namespace odonata::sysid

#include <random>

#include <gtest/gtest.h>

#include "sysid/arx_model.hpp"

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

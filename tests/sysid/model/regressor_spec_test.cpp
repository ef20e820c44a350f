#include <gtest/gtest.h>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {
namespace {

Series Ramp(int n) {
  Series s;
  s.outputs.resize(n, 1);
  s.inputs.resize(n, 2);
  for (int t = 0; t < n; ++t) {
    s.outputs(t, 0) = 100 + t;
    s.inputs(t, 0) = 200 + t;
    s.inputs(t, 1) = 300 + t;
  }
  return s;
}

TEST(RegressorSpec, Equation7WithDelayOne) {
  RegressorSpec spec{2, 3, 1, {"y"}, {"a", "b"}};
  EXPECT_EQ(spec.size(), 8);
  EXPECT_EQ(spec.first_target(), 3);  // u(k−2) must exist for target k+1
  const RegressionData d = BuildRegression(spec, Ramp(10));
  ASSERT_EQ(d.x.rows(), 7);
  // Target t = 3: y(2), y(1), a(2), a(1), a(0), b(2), b(1), b(0).
  Eigen::VectorXd expect(8);
  expect << 102, 101, 202, 201, 200, 302, 301, 300;
  EXPECT_EQ(d.x.row(0).transpose(), expect);
  EXPECT_EQ(d.y(0, 0), 103);
  const auto names = spec.RegressorNames();
  EXPECT_EQ(names.front(), "y(k)");
  EXPECT_EQ(names[1], "y(k-1)");
  EXPECT_EQ(names[2], "a(k)");
  EXPECT_EQ(spec.TargetName(0), "y(k+1)");
}

TEST(RegressorSpec, DelayZeroIsStaticRegressionWithoutOutputLags) {
  RegressorSpec spec{0, 1, 0, {"y"}, {"a", "b"}};
  EXPECT_EQ(spec.first_target(), 0);
  const RegressionData d = BuildRegression(spec, Ramp(5));
  ASSERT_EQ(d.x.rows(), 5);
  EXPECT_EQ(d.x(2, 0), 202);  // same row's input
  EXPECT_EQ(d.x(2, 1), 302);
  EXPECT_EQ(d.y(2, 0), 102);
  EXPECT_EQ(spec.RegressorNames().front(), "a(k)");
  EXPECT_EQ(spec.TargetName(0), "y(k)");
}

TEST(RegressorSpec, ReportsEveryProblemAtOnce) {
  RegressorSpec spec{-1, 1, 2, {}, {}};
  const std::string p = spec.Problems();
  EXPECT_NE(p.find("no output"), std::string::npos);
  EXPECT_NE(p.find("delay"), std::string::npos);
  EXPECT_NE(p.find("output lags"), std::string::npos);
  EXPECT_NE(p.find("no input"), std::string::npos);
}

TEST(RegressorSpec, SeriesThatDoesNotMatchTheSpecIsAnError) {
  RegressorSpec spec{1, 1, 1, {"y"}, {"a"}};  // Ramp has two inputs
  EXPECT_THROW(BuildRegression(spec, Ramp(5)), std::invalid_argument);
}

TEST(RegressorSpec, TooShortSeriesIsAnError) {
  RegressorSpec spec{3, 3, 1, {"y"}, {"a", "b"}};
  EXPECT_THROW(BuildRegression(spec, Ramp(3)), std::invalid_argument);
}

}  // namespace
}  // namespace odonata::sysid

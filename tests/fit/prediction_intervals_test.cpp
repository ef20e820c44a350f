// Split-conformal prediction intervals (fit/prediction_intervals.hpp; issue 60 point 1), scored by
// Evaluate as odonata-fit scores the validation file: with the true model of a noisy linear plant
// as the predictor, intervals calibrated on one stretch cover about their level on another
// (exchangeable) stretch, one step ahead, K steps ahead and in free run; the half width is the
// ⌈(n+1)·level⌉-th smallest |residual|; a level outside (0, 1) is refused.
#include "fit/prediction_intervals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "fit/fit_scoring.hpp"
#include "linear_plant.hpp"

namespace odonata::fit {
namespace {

sysid::RegressorSpec Spec() { return testing::LinearPlantSpec(); }

// y(t) = 0.7 y(t−1) + 0.5 u(t−1) + e(t), e ~ N(0, 0.1²).
sysid::Series Plant(unsigned seed, int samples) {
  return testing::LinearPlant(seed, samples, 0.1, 0.1);
}

// The plant's own one-step map on the regressor [y(t−1), u(t−1)].
const sysid::Predictor kTrue = [](const Eigen::VectorXd& x) {
  return Eigen::VectorXd::Constant(1, 0.7 * x(0) + 0.5 * x(1));
};

TEST(PredictionIntervals, CalibratedOnOneStretchTheyCoverTheirLevelOnAnother) {
  const IntervalWidths w = CalibrateIntervals(Spec(), Plant(1, 3000), kTrue, 5, 0.9);
  ASSERT_EQ(w.calibration_rows, 2999);
  const std::vector<nlohmann::json> blocks = Evaluate(Spec(), Plant(2, 3000), kTrue, 5, &w);
  for (const char* mode : {"one_step", "k_step", "free_run"}) {
    SCOPED_TRACE(mode);
    const nlohmann::json& i = blocks[0][mode]["interval"];
    EXPECT_EQ(i["level"].get<double>(), 0.9);
    EXPECT_GE(i["coverage"].get<double>(), 0.87);
    EXPECT_LE(i["coverage"].get<double>(), 0.93);
  }
  // One step ahead the residual is the noise: the half width is its 90 % quantile, 1.645 σ.
  EXPECT_NEAR(w.half_width.at("one_step")(0), 1.645 * 0.1, 0.01);
  // Farther ahead the errors add up: wider.
  EXPECT_GT(w.half_width.at("k_step")(0), w.half_width.at("one_step")(0));
  EXPECT_GT(w.half_width.at("free_run")(0), w.half_width.at("k_step")(0));
}

TEST(PredictionIntervals, TheHalfWidthIsTheConformalOrderStatistic) {
  // Nine targets, residuals 1 … 9 one step ahead: at 0.8, ⌈10·0.8⌉ = 8 → 8; at 0.95 → 10 > 9:
  // unbounded.
  sysid::Series s;
  s.outputs = Eigen::MatrixXd::Zero(10, 1);
  s.inputs = Eigen::MatrixXd::Zero(10, 1);
  for (int t = 1; t < 10; ++t) s.outputs(t, 0) = t;
  const sysid::Predictor zero = [](const Eigen::VectorXd&) { return Eigen::VectorXd::Zero(1); };
  EXPECT_EQ(CalibrateIntervals(Spec(), s, zero, 0, 0.8).half_width.at("one_step")(0), 8.0);
  EXPECT_TRUE(
      std::isinf(CalibrateIntervals(Spec(), s, zero, 0, 0.95).half_width.at("one_step")(0)));
  EXPECT_THROW(CalibrateIntervals(Spec(), s, zero, 0, 1.0), std::invalid_argument);
  EXPECT_THROW(CalibrateIntervals(Spec(), s, zero, 0, 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace odonata::fit

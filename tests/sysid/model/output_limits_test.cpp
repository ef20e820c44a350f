// Saturation limits found in the training outputs (docs/identifier.md §7.2): what counts as a
// saturation, how predictions are held, and that a model keeps its limits when saved.
#include "sysid/model/output_limits.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// A lower tank that overflows: its level follows the inflow but never passes 10.
Series Overflowing(int samples) {
  std::mt19937_64 rng(4);
  std::uniform_real_distribution<double> level(0.0, 1.0);
  Series s;
  s.inputs.resize(samples, 1);
  s.outputs.resize(samples, 1);
  double u = 0, x = 5;
  for (int k = 0; k < samples; ++k) {
    if (k % 40 == 0) u = level(rng);
    s.inputs(k, 0) = u;
    s.outputs(k, 0) = x;
    x = std::min(10.0, 0.9 * x + 1.5 * u);
  }
  return s;
}

TEST(OutputLimits, ASaturatedExtremeIsALimitAndANoisyOneIsNot) {
  const Series s = Overflowing(2000);
  ASSERT_GT((s.outputs.array() == 10.0).count(), 100);
  const OutputLimits l = OutputLimits::Detect(s.outputs);
  ASSERT_TRUE(l.any());
  EXPECT_EQ(l.upper(0), 10.0);
  EXPECT_EQ(l.lower(0), -kInf) << "the bottom is reached once, not held";

  Eigen::MatrixXd y(200, 1);
  for (int k = 0; k < 200; ++k) y(k, 0) = std::sin(0.1 * k);
  EXPECT_FALSE(OutputLimits::Detect(y).any()) << "a sine touches its extremes";
  // Held, but too briefly: four samples in a row.
  y.block(50, 0, 4, 1).setConstant(3.0);
  EXPECT_FALSE(OutputLimits::Detect(y).any());
  // Held five in a row, but on less than 1 % of a long record.
  Eigen::MatrixXd long_y(1000, 1);
  for (int k = 0; k < 1000; ++k) long_y(k, 0) = std::sin(0.1 * k);
  long_y.block(500, 0, 5, 1).setConstant(3.0);
  EXPECT_FALSE(OutputLimits::Detect(long_y).any());
  long_y.block(600, 0, 6, 1).setConstant(3.0);  // 11 samples: over 1 %
  const OutputLimits top = OutputLimits::Detect(long_y);
  ASSERT_TRUE(top.any());
  EXPECT_EQ(top.upper(0), 3.0);
  // A constant output has no range to hold.
  EXPECT_FALSE(OutputLimits::Detect(Eigen::MatrixXd::Constant(100, 1, 2.0)).any());
}

TEST(OutputLimits, HoldsPredictionsAndRoundTripsThroughJson) {
  OutputLimits l;
  l.lower = Eigen::Vector2d(-kInf, 0.0);
  l.upper = Eigen::Vector2d(10.0, kInf);
  EXPECT_EQ(l.Apply(0, 12.0), 10.0);
  EXPECT_TRUE(l.Holds(0, 12.0));
  EXPECT_EQ(l.Apply(0, -1e9), -1e9);
  EXPECT_EQ(l.Apply(1, -1.0), 0.0);
  EXPECT_FALSE(l.Holds(1, 3.0));
  EXPECT_TRUE(std::isnan(l.Apply(0, std::nan(""))));
  const nlohmann::json j = l.ToJson();
  EXPECT_TRUE(j["lower"][0].is_null());
  const OutputLimits back = OutputLimits::FromJson(j, 2);
  EXPECT_EQ(back.lower(1), 0.0);
  EXPECT_EQ(back.upper(0), 10.0);
  EXPECT_EQ(back.upper(1), kInf);
  EXPECT_THROW(OutputLimits::FromJson(j, 3), std::runtime_error);
  nlohmann::json crossed = j;
  crossed["lower"][0] = 11.0;
  EXPECT_THROW(OutputLimits::FromJson(crossed, 2), std::runtime_error);
  EXPECT_TRUE(OutputLimits{}.Problems(3).empty()) << "no limits fit any output count";
  OutputLimits nan = l;
  nan.upper(1) = std::nan("");
  EXPECT_FALSE(nan.Problems(2).empty());
}

// A model trained on the overflowing tank holds its free run at the overflow, as the tank does,
// and keeps the limit through a save.
TEST(OutputLimits, AModelHoldsItsFreeRunAtTheSaturationAndSavesIt) {
  RegressorSpec spec;
  spec.outputs = {"level"};
  spec.inputs = {"inflow"};
  spec.output_lags = 1;
  spec.input_lags = 1;
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.max_rules = 1;
  cfg.entropy.threshold = 0.0;
  NarxModel m(spec, cfg);
  const Series s = Overflowing(2000);
  Train(m, s, TrainOptions{});
  ASSERT_TRUE(m.limits().any());
  EXPECT_EQ(m.limits().upper(0), 10.0);
  Eigen::VectorXd x(2);
  x << 10.0, 1.0;  // full tank, full inflow: the linear model says more than 10
  EXPECT_EQ(m.Predict(x)(0), 10.0);

  NarxModel unlimited(spec, cfg);
  TrainOptions off;
  off.detect_output_limits = false;
  Train(unlimited, s, off);
  EXPECT_FALSE(unlimited.limits().any());
  EXPECT_GT(unlimited.Predict(x)(0), 10.0);
  EXPECT_LT(m.Ndei(s, true), unlimited.Ndei(s, true)) << "held, the free run follows the tank";

  const NarxModel back = NarxModel::FromJson(m.ToJson());
  ASSERT_TRUE(back.limits().any());
  EXPECT_EQ(back.limits().upper(0), 10.0);
  EXPECT_EQ(back.Predict(x)(0), 10.0);
  EXPECT_FALSE(unlimited.ToJson().contains("output_limits")) << "files without limits unchanged";
}

}  // namespace
}  // namespace odonata::sysid

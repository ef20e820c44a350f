#include "plant/wing_beat_averager.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace odonata::plant {
namespace {

TEST(WingBeatAverager, ConstantInputAveragesToItself) {
  WingBeatAverager avg(0.0025, 0.5);
  WingForceXz f;
  f << 1, 2, 3, 4, 5, 6, 7, 8;
  for (int k = 0; k < 300; ++k) avg.Push(f);
  const WingForceXz mean = avg.Average(Eigen::Vector4d(0.1, 0.2, 0.177, 1.0));
  EXPECT_LT((mean - f).cwiseAbs().maxCoeff(), 1e-12);
}

// A sine sampled at step midpoints averages to ~0 over exactly one of its periods, including a
// period that is not a whole number of steps (the oldest step is weighted by its fraction).
TEST(WingBeatAverager, SineAveragesToZeroOverOnePeriod) {
  const double step_s = 0.0025;
  const double period_s = 1.0 / 5.3;
  WingBeatAverager avg(step_s, 0.5);
  for (int k = 0; k < 400; ++k) {
    WingForceXz f = WingForceXz::Zero();
    f(0, 1) = 1.0 + std::sin(2.0 * M_PI * (k + 0.5) * step_s / period_s);
    avg.Push(f);
  }
  const WingForceXz mean = avg.Average(Eigen::Vector4d::Constant(period_s));
  EXPECT_NEAR(mean(0, 1), 1.0, 2e-3);
}

TEST(WingBeatAverager, EmptyHistoryIsZero) {
  const WingBeatAverager avg(0.0025, 0.5);
  EXPECT_EQ(avg.Average(Eigen::Vector4d::Constant(0.2)).cwiseAbs().maxCoeff(), 0.0);
}

}  // namespace
}  // namespace odonata::plant

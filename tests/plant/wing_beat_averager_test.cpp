#include "plant/wing_beat_averager.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

TEST(BeatSignalAverager, ConstantAveragesToItselfAndEmptyIsZero) {
  BeatSignalAverager avg(0.0025, 0.5);
  EXPECT_EQ(avg.Average(0.2).cwiseAbs().maxCoeff(), 0.0);
  BeatVector v;
  for (int i = 0; i < kBeatSignalCount; ++i) v(i) = 0.5 * i - 2.0;
  for (int k = 0; k < 300; ++k) avg.Push(v);
  for (const double window_s : {0.001, 0.1, 0.187, 0.5, 3.0}) {
    EXPECT_LT((avg.Average(window_s) - v).cwiseAbs().maxCoeff(), 1e-12) << window_s;
  }
}

// The window covers the newest whole steps plus a fraction of the step before; a shorter history
// is averaged whole.
TEST(BeatSignalAverager, WeighsTheOldestStepByItsFraction) {
  BeatSignalAverager avg(0.01, 0.5);
  const auto push = [&avg](double x) { avg.Push(BeatVector::Constant(x)); };
  push(1.0);
  EXPECT_DOUBLE_EQ(avg.Average(0.035)(kBeatVz), 1.0);  // one step of history
  push(2.0);
  push(3.0);
  push(4.0);
  push(5.0);
  // 3.5 steps: 5, 4, 3 whole and half of 2.
  EXPECT_NEAR(avg.Average(0.035)(kBeatRoll), (5.0 + 4.0 + 3.0 + 0.5 * 2.0) / 3.5, 1e-12);
  EXPECT_NEAR(avg.Average(0.01)(kBeatFz), 5.0, 1e-12);
  EXPECT_NEAR(avg.Average(1.0)(kBeatP), 3.0, 1e-12);  // whole history: 1 … 5
}

// A sine of the beat frequency averages out over one beat, wherever the window ends.
TEST(BeatSignalAverager, RemovesASineOfTheWindowsPeriod) {
  const double step_s = 0.0025, period_s = 1.0 / 5.36;
  BeatSignalAverager avg(step_s, 0.5);
  double worst = 0.0;
  for (int k = 0; k < 600; ++k) {
    avg.Push(BeatVector::Constant(0.3 + 0.19 * std::sin(2.0 * M_PI * k * step_s / period_s)));
    if (k > 200) worst = std::max(worst, std::fabs(avg.Average(period_s)(kBeatVz) - 0.3));
  }
  EXPECT_LT(worst, 0.19 * 0.02);
}

}  // namespace
}  // namespace odonata::plant

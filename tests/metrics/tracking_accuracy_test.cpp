// TrackingAccuracy: the window's error against the span's spread, steady while the vehicle
// holds a level, where a window FIT swings.

#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "metrics/running_accuracy.hpp"
#include "metrics/tracking_accuracy.hpp"

namespace odonata::metrics {
namespace {

TEST(TrackingAccuracy, StaysSteadyOnHeldLevelsWhereTheWindowFitSwings) {
  TrackingAccuracy tracking(100, 1000);
  WindowAccuracy window(100);
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.02);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  double y = 0.0;
  double tracking_min = 1e9, tracking_max = -1e9, window_min = 1e9, window_max = -1e9;
  for (int k = 0; k < 20000; ++k) {
    if (k % 250 == 0) y = level(rng);  // a level held 2.5 s
    const double yhat = y + noise(rng);
    tracking.Add(y, yhat);
    window.Add(y, yhat);
    if (k < 2000 || !window.full()) continue;
    const double t = tracking.fit_percent(), w = window.Get().fit_percent;
    tracking_min = std::min(tracking_min, t);
    tracking_max = std::max(tracking_max, t);
    if (std::isfinite(w)) {
      window_min = std::min(window_min, w);
      window_max = std::max(window_max, w);
    }
  }
  // Error 0.02 against a spread of ≈ 0.58: FIT ≈ 96.5 %; a span of only four levels can be
  // narrower, so it dips, but by points, not by the hundreds of the window FIT.
  EXPECT_GT(tracking_min, 80.0);
  EXPECT_LT(tracking_max, 99.0);
  // The window's own spread is ~0 while a level is held: its FIT falls far below.
  EXPECT_LT(window_min, 0.0);
}

TEST(TrackingAccuracy, FollowsAChangeInTheErrorWithinAWindow) {
  TrackingAccuracy tracking(50, 500);
  for (int k = 0; k < 1000; ++k) {
    const double y = std::sin(0.05 * k);
    tracking.Add(y, y + (k < 800 ? 0.01 : 0.2) * std::cos(1.3 * k));
  }
  // 0.2·cos has RMS 0.14 against a sine's std of 0.71: FIT ≈ 80 %.
  EXPECT_NEAR(tracking.fit_percent(), 80.0, 3.0);
}

TEST(TrackingAccuracy, NotReadyUntilTheSpanIsFullAndIgnoresNaN) {
  TrackingAccuracy tracking(10, 20);
  for (int k = 0; k < 19; ++k) tracking.Add(k, k);
  EXPECT_FALSE(tracking.ready());
  EXPECT_TRUE(std::isnan(tracking.fit_percent()));
  tracking.Add(std::nan(""), 1.0);
  EXPECT_FALSE(tracking.ready());
  tracking.Add(19.0, 19.0);
  EXPECT_TRUE(tracking.ready());
  EXPECT_DOUBLE_EQ(tracking.fit_percent(), 100.0);
}

}  // namespace
}  // namespace odonata::metrics

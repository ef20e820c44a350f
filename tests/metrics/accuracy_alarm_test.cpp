// The live accuracy alarm: a sudden loss raises it, a return to the settled level clears it.

#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "metrics/accuracy_alarm.hpp"

namespace odonata::metrics {
namespace {

/// A predictor whose error grows from `small` to `large` at sample `change` and shrinks back
/// linearly over `recover` samples.
std::vector<AccuracyEvent> Simulate(long change, long recover, double small, double large) {
  AccuracyAlarm alarm;
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  std::vector<AccuracyEvent> events;
  for (long k = 0; k < 4000; ++k) {
    const double y = std::sin(0.07 * k) + 0.3 * std::sin(0.31 * k);
    double level = small;
    if (k >= change) level = large - (large - small) * std::min(1.0, double(k - change) / recover);
    if (const auto e = alarm.Push(k, y, y + level * n(rng))) events.push_back(*e);
  }
  return events;
}

TEST(AccuracyAlarm, RaisesWithinAWindowOfTheChangeAndClearsOnRecovery) {
  const auto events = Simulate(2000, 800, 0.02, 0.3);
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, AccuracyEvent::Kind::kAlarm);
  EXPECT_GE(events[0].sample, 2000);
  EXPECT_LE(events[0].sample, 2100) << "within one window (1 s at 100 Hz)";
  EXPECT_GT(events[0].reference_fit, 95.0);
  EXPECT_EQ(events[1].kind, AccuracyEvent::Kind::kRecovered);
  EXPECT_GT(events[1].sample, 2400);
  EXPECT_GE(events[1].window_fit, events[1].reference_fit - 1.0);
}

TEST(AccuracyAlarm, StaysQuietWithoutAChange) {
  EXPECT_TRUE(Simulate(100000, 1, 0.02, 0.02).empty());
}

TEST(AccuracyAlarm, IgnoresNonFiniteSamples) {
  AccuracyAlarm alarm;
  for (long k = 0; k < 500; ++k) EXPECT_FALSE(alarm.Push(k, std::nan(""), 1.0).has_value());
  EXPECT_FALSE(alarm.alarmed());
}

}  // namespace
}  // namespace odonata::metrics

// One grid for signals at several rates: the rate every signal fills, flags held, the gap rule,
// windows, and the straight line the gap rule bridges with.
#include "timeseries/uniform_grid.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "timeseries/gap_rule.hpp"

namespace odonata::timeseries {
namespace {

// A signal v = slope · t sampled at `rate_hz` from `t0` for `seconds`.
TimedSignal Ramp(const std::string& name, double rate_hz, double slope, double t0 = 0.0,
                 double seconds = 2.0) {
  TimedSignal s{name, {}, {}, Interpolation::kLinear};
  for (int i = 0; i <= static_cast<int>(seconds * rate_hz); ++i) {
    const double t = t0 + i / rate_hz;
    s.t_s.push_back(t);
    s.values.push_back(slope * t);
  }
  return s;
}

TEST(UniformGrid, TheDefaultRateIsTheSlowestSignalsWhichEverySignalFills) {
  // Gyro at 400 Hz, torque at 100 Hz, motors at 50 Hz: the grid is 50 Hz, no cell a gap.
  const UniformGrid g = Resample(
      {Ramp("gyro", 400, 1.0), Ramp("torque", 100, 2.0), Ramp("motor", 50, 3.0)}, GridOptions{});
  EXPECT_TRUE(g.rate_chosen);
  EXPECT_NEAR(g.rate_hz, 50.0, 1e-9);
  EXPECT_EQ(g.slowest, 2u);
  ASSERT_EQ(g.t_s.size(), 101u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(g.signals[k].gap_cells, 0u) << k;
    for (std::size_t i = 0; i < g.t_s.size(); ++i)
      EXPECT_NEAR(g.columns[k][i], (k + 1.0) * g.t_s[i], 1e-9) << k << " " << i;
  }
  EXPECT_NEAR(g.signals[0].median_rate_hz, 400.0, 1e-6);
  // The same signals on a 400 Hz grid: the motors' samples are 8 periods apart, beyond the gap
  // rule, so its cells between samples are gaps.
  GridOptions fast;
  fast.rate_hz = 400;
  const UniformGrid f = Resample({Ramp("gyro", 400, 1.0), Ramp("motor", 50, 3.0)}, fast);
  EXPECT_FALSE(f.rate_chosen);
  EXPECT_GT(f.signals[1].gap_cells, f.t_s.size() / 2);
}

TEST(UniformGrid, FlagsAreHeldNeverInterpolated) {
  // A landed flag at 1 Hz (and on change): 1 until 0.5 s, then 0.
  TimedSignal landed{"landed", {0.0, 0.5, 1.0, 2.0}, {1, 0, 0, 0}, Interpolation::kHold};
  const UniformGrid g = Resample({Ramp("gyro", 16, 1.0), landed}, GridOptions{});
  for (std::size_t i = 0; i < g.t_s.size(); ++i) {
    const double v = g.columns[1][i];
    EXPECT_TRUE(v == 0.0 || v == 1.0) << v;  // never 0.8125
    EXPECT_EQ(v, g.t_s[i] < 0.5 ? 1.0 : 0.0) << g.t_s[i];
  }
  EXPECT_EQ(g.signals[1].gap_cells, 0u);  // held signals have no gap limit
  // The flag's slow rate does not choose the grid.
  EXPECT_NEAR(g.rate_hz, 16.0, 1e-9);
}

TEST(UniformGrid, AWindowCutsTheSpan) {
  GridOptions o;
  o.from_s = 0.5;
  o.to_s = 1.0;
  const UniformGrid g = Resample({Ramp("a", 100, 1.0)}, o);
  EXPECT_DOUBLE_EQ(g.t_s.front(), 0.5);
  EXPECT_NEAR(g.t_s.back(), 1.0, 1e-9);
  EXPECT_EQ(g.t_s.size(), 51u);
  o.from_s = 5.0;
  o.to_s = 6.0;
  EXPECT_THROW(Resample({Ramp("a", 100, 1.0)}, o), std::invalid_argument);  // outside
  o.from_s = 1.0;
  o.to_s = 0.5;
  EXPECT_THROW(Resample({Ramp("a", 100, 1.0)}, o), std::invalid_argument);  // backwards
}

TEST(UniformGrid, GapsBeyondTheRuleAreNaNAndMissingCellsAreNoSamples) {
  TimedSignal a = Ramp("a", 100, 1.0);
  for (int i = 50; i <= 55; ++i) a.values[static_cast<std::size_t>(i)] = std::nan("");
  GridOptions o;
  o.rate_hz = 100;
  o.max_gap = 5;
  const UniformGrid g = Resample({a}, o);
  EXPECT_TRUE(std::isnan(g.columns[0][52]));
  EXPECT_EQ(g.signals[0].gap_cells, 6u);
  o.max_gap = 6;
  const UniformGrid h = Resample({a}, o);
  EXPECT_NEAR(h.columns[0][52], 0.52, 1e-12);
  EXPECT_EQ(h.signals[0].bridged_cells, 6u);
}

TEST(UniformGrid, RefusesWhatItCannotDo) {
  EXPECT_THROW(Resample({}, GridOptions{}), std::invalid_argument);
  GridOptions bad;
  bad.rate_hz = -1;
  EXPECT_THROW(Resample({Ramp("a", 10, 1)}, bad), std::invalid_argument);
  EXPECT_THROW(Resample({TimedSignal{"e", {}, {}, Interpolation::kLinear}}, GridOptions{}),
               std::invalid_argument);
  EXPECT_THROW(Resample({Ramp("a", 10, 1, 0.0, 1.0), Ramp("b", 10, 1, 5.0, 1.0)}, GridOptions{}),
               std::invalid_argument);  // no overlap
  GridOptions huge;
  huge.rate_hz = 1e9;
  EXPECT_THROW(Resample({Ramp("a", 10, 1)}, huge), std::invalid_argument);
}

TEST(GapRule, BridgesShortRunsOnTheStraightLineAndLeavesLongOnes) {
  std::vector<double> v{0, NAN, NAN, 3, NAN, NAN, NAN, 7, NAN};
  EXPECT_EQ(BridgeRuns(&v, 2), 2);
  EXPECT_DOUBLE_EQ(v[1], 1.0);
  EXPECT_DOUBLE_EQ(v[2], 2.0);
  EXPECT_TRUE(std::isnan(v[5]));  // a run of 3 > 2
  EXPECT_TRUE(std::isnan(v[8]));  // at the end
  EXPECT_TRUE(Bridges(2, 2));
  EXPECT_FALSE(Bridges(3, 2));
  EXPECT_FALSE(Bridges(0, 2));
  EXPECT_DOUBLE_EQ(Bridge(0.0, 3.0, 1, 3), 1.0);
}

}  // namespace
}  // namespace odonata::timeseries

// The online identifier's live prediction intervals (issue 60 point 1; sysid/online/
// live_intervals): conformal half widths of the residuals of earlier samples cover about the
// level on later ones, are unknown (+∞) until there are enough, and the identifier's reports
// carry them, frozen with learning.
#include "sysid/online/live_intervals.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "online_fixtures.hpp"

namespace odonata::sysid {
namespace {

TEST(LiveIntervals, CoverAboutTheLevelOfResidualsLikeTheOnesTheyCameFrom) {
  LiveIntervals live(0.9);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  std::normal_distribution<double> drift(0.0, 1.0);  // the free run's error, wider
  const Eigen::VectorXd none;
  int scored = 0, covered = 0, free_covered = 0;
  for (int k = 0; k < 12000; ++k) {
    Eigen::VectorXd y(1), yhat(1), free(1);
    yhat(0) = std::sin(0.01 * k);
    y(0) = yhat(0) + noise(rng);
    free(0) = y(0) + drift(rng);
    if (k < 8) {
      EXPECT_TRUE(live.one_step().size() == 0 || std::isinf(live.one_step()(0))) << k;
    }
    if (k >= 2000) {  // a full window behind it
      ++scored;
      if (std::abs(y(0) - yhat(0)) <= live.one_step()(0)) ++covered;
      if (std::abs(y(0) - free(0)) <= live.free_run()(0)) ++free_covered;
    }
    live.Add(y, yhat, none, free);
  }
  const double coverage = static_cast<double>(covered) / scored;
  EXPECT_GT(coverage, 0.88);
  EXPECT_LT(coverage, 0.92);
  // The 90 % quantile of |N(0, 0.5²)| is 0.5 · 1.645.
  EXPECT_NEAR(live.one_step()(0), 0.822, 0.06);
  EXPECT_NEAR(static_cast<double>(free_covered) / scored, 0.9, 0.02);
  EXPECT_NEAR(live.free_run()(0), 1.645, 0.12);
  EXPECT_EQ(live.ahead().size(), 0);  // no horizon: no K-step width
  live.Clear();
  EXPECT_EQ(live.one_step().size(), 0);
  EXPECT_EQ(live.free_run().size(), 0);
  EXPECT_THROW(LiveIntervals(1.0), std::invalid_argument);
}

// A seed replaces the window: its widths are the seed's conformal ranks, the K-step ones only for
// the horizon the reports carry, and only its newest kWindow rows count.
TEST(LiveIntervals, ASeedStartsTheWindowFromItsResiduals) {
  LiveIntervals live(0.9);
  const Eigen::VectorXd y = Eigen::VectorXd::Constant(1, 10.0), zero = Eigen::VectorXd::Zero(1);
  for (int k = 0; k < 100; ++k) live.Add(y, zero, zero, zero);  // residuals of 10 everywhere
  EXPECT_EQ(live.one_step()(0), 10.0);
  SeedResiduals seed;
  seed.one_step.resize(9, 1);
  for (int r = 0; r < 9; ++r) seed.one_step(r, 0) = -(r + 1.0);  // |e| = 1 … 9: ⌈10·0.9⌉ = 9th
  seed.ahead = 2.0 * seed.one_step;
  seed.free_run = 3.0 * seed.one_step;
  seed.horizon = 5;
  live.Seed(seed, 5);
  EXPECT_EQ(live.one_step()(0), 9.0);
  EXPECT_EQ(live.ahead()(0), 18.0);
  EXPECT_EQ(live.free_run()(0), 27.0);
  live.Seed(seed, 20);  // another horizon: no K-step width from it
  EXPECT_EQ(live.one_step()(0), 9.0);
  EXPECT_EQ(live.ahead().size(), 0);
  // Older rows beyond the window leave: 10 000 rows of 100, then kWindow rows of 1.
  SeedResiduals long_seed;
  long_seed.one_step = Eigen::MatrixXd::Constant(10000 + LiveIntervals::kWindow, 1, 1.0);
  long_seed.one_step.topRows(10000).setConstant(100.0);
  live.Seed(long_seed, 0);
  EXPECT_EQ(live.one_step()(0), 1.0);
  EXPECT_EQ(live.free_run().size(), 0);
}

TEST(LiveIntervals, TheIdentifierReportsThemAndKeepsThemWhenFrozen) {
  using testing::Empty;
  using testing::Row;
  const Series s = testing::NarendraTrain(3000, 5);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, s));
  id.set_ahead_horizon(5);
  std::optional<SampleReport> last;
  for (Eigen::Index k = 0; k < 2000; ++k)
    if (auto r = id.Push(Row(s, k))) last = r;
  ASSERT_TRUE(last);
  EXPECT_DOUBLE_EQ(last->interval_level, 0.9);
  ASSERT_EQ(last->half_width.size(), 1);
  ASSERT_EQ(last->ahead_half_width.size(), 1);
  EXPECT_TRUE(std::isfinite(last->half_width(0)) && last->half_width(0) > 0.0);
  EXPECT_GT(last->ahead_half_width(0), 0.0);
  // And around the free run, from its own residuals.
  ASSERT_EQ(last->free_run_half_width.size(), 1);
  EXPECT_TRUE(std::isfinite(last->free_run_half_width(0)) && last->free_run_half_width(0) > 0.0);
  // Has the model seen enough: one state per output at every sample, the watch's own.
  ASSERT_EQ(last->seen_enough.size(), 1u);
  EXPECT_EQ(last->seen_enough[0], id.Settling()[0].state);
  id.Freeze();
  const auto at_freeze = id.Push(Row(s, 2000));
  ASSERT_TRUE(at_freeze);
  const double frozen = at_freeze->half_width(0);
  int covered = 0, scored = 0;
  for (Eigen::Index k = 2001; k < 3000; ++k) {
    const auto r = id.Push(Row(s, k));
    ASSERT_TRUE(r);
    EXPECT_EQ(r->half_width(0), frozen);  // a frozen model learns no residual either
    EXPECT_EQ(r->free_run_half_width(0), at_freeze->free_run_half_width(0));
    ++scored;
    if (std::abs(r->measured(0) - r->predicted(0)) <= r->half_width(0)) ++covered;
  }
  std::printf("Narendra, frozen after 2000 samples: %d of %d within the 90 %% interval\n", covered,
              scored);
  // The same plant and input: within issue 60's band around the level.
  EXPECT_GE(covered, 0.85 * scored);
  EXPECT_LE(covered, 0.95 * scored);
}

}  // namespace
}  // namespace odonata::sysid

#include <gtest/gtest.h>

#include "narendra_series.hpp"
#include "sysid/entropy_sweep.hpp"

namespace odonata::sysid {
namespace {

TEST(EntropySweep, PicksTheSmallestModelWithinTolerance) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  SweepOptions o;
  o.thresholds = {0.003, 0.03, 0.1, 0.3};
  o.tolerance_percent = 2.0;
  const SweepResult r =
      SweepEntropyThreshold(testing::NarendraSpec(), cfg, TrainOptions{},
                            testing::NarendraTrain(2000), testing::NarendraValidate(), o);
  ASSERT_EQ(r.points.size(), 4u);
  const auto& best = r.points[r.best];
  const auto& chosen = r.points[r.chosen];
  for (const auto& p : r.points) EXPECT_LE(p.validation_fit_percent, best.validation_fit_percent);
  EXPECT_GE(chosen.validation_fit_percent, best.validation_fit_percent - 2.0);
  EXPECT_LE(chosen.rules, best.rules);
  for (const auto& p : r.points) {
    if (p.validation_fit_percent >= best.validation_fit_percent - 2.0) {
      EXPECT_GE(p.rules, chosen.rules);
    }
  }
  EXPECT_LT(r.points.front().rules, r.points.back().rules);
}

TEST(EntropySweep, DefaultThresholdsSpanThePapersRange) {
  const auto t = DefaultThresholds();
  EXPECT_LE(t.front(), 0.001 + 1e-12);
  EXPECT_GE(t.back(), 0.25);
  for (std::size_t k = 1; k < t.size(); ++k) EXPECT_GT(t[k], t[k - 1]);
}

}  // namespace
}  // namespace odonata::sysid

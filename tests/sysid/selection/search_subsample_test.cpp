// A long record's settings are chosen on blocks spread over it, and the chosen setting is then
// trained on every row (issue 22, docs/identifier.md §9 "Long records").
#include "sysid/selection/search_subsample.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <nlohmann/json.hpp>
#include <sstream>

#include "narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {
namespace {

Series Ramp(Eigen::Index n) {
  Series s;
  s.outputs = Eigen::VectorXd::LinSpaced(n, 0.0, double(n - 1));
  s.inputs = -s.outputs;
  return s;
}

TEST(SearchSubsample, AShortRecordIsSearchedWhole) {
  const Series s = Ramp(1000);
  const Series out = SubsampleForSearch(s, {1000, 4});
  EXPECT_EQ(out.outputs, s.outputs);
  EXPECT_TRUE(out.breaks.empty());
  EXPECT_EQ(SubsampleForSearch(s, {0, 4}).samples(), 1000);  // 0: no budget
}

TEST(SearchSubsample, BlocksSpanTheRecordFromItsStartToItsEnd) {
  const Series s = Ramp(10000);
  const Series out = SubsampleForSearch(s, {2000, 4});
  ASSERT_EQ(out.samples(), 2000);
  EXPECT_EQ(out.breaks, (std::vector<Eigen::Index>{500, 1000, 1500}));
  // Each block is contiguous, the first starts the record and the last ends it, in order.
  EXPECT_EQ(out.outputs(0, 0), 0.0);
  EXPECT_EQ(out.outputs(1999, 0), 9999.0);
  for (Eigen::Index b = 0; b < 4; ++b) {
    const double first = out.outputs(b * 500, 0);
    for (Eigen::Index k = 1; k < 500; ++k)
      EXPECT_EQ(out.outputs(b * 500 + k, 0), first + double(k));
    if (b > 0) {
      EXPECT_GT(first, out.outputs(b * 500 - 1, 0));
    }
  }
  EXPECT_EQ(out.inputs, -out.outputs);
}

TEST(SearchSubsample, TheRecordsOwnBreaksAreKept) {
  Series s = Ramp(10000);
  s.breaks = {100, 9800};  // inside the first and the last block
  const Series out = SubsampleForSearch(s, {2000, 4});
  EXPECT_EQ(out.breaks, (std::vector<Eigen::Index>{100, 500, 1000, 1500, 1800}));
}

OfflineFitOptions SmallSearch() {
  OfflineFitOptions o;
  o.selection.consequents = {fuzzy::ConsequentKind::kLinear};
  o.selection.thresholds = {ThresholdForRadius(1.3), ThresholdForRadius(0.9)};
  o.selection.kappas = {1.0};
  o.selection.max_epochs = 8;
  o.search_budget = {1200, 4};
  return o;
}

// The search sees the budget, the final model every row; and it is the same model whatever the
// thread count.
TEST(SearchSubsample, FitOfflineSearchesTheBlocksAndTrainsOnEveryRow) {
  const Series train = testing::NarendraTrain(6000);
  OfflineFitOptions o = SmallSearch();
  std::vector<std::string> models;
  for (unsigned threads : {1u, 2u}) {
    o.selection.threads = threads;
    const OfflineFit fit =
        FitOffline(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, o);
    ASSERT_TRUE(fit.selection);
    EXPECT_EQ(fit.searched_rows, 1200);
    EXPECT_EQ(fit.selection->fit_samples + fit.selection->holdout_samples, 1200);
    models.push_back(fit.model.ToJson().dump());
    if (threads == 1) {
      // Trained on all 6000 rows: its one-step error on the rows no block held is as low as on
      // the blocks' (a model fitted to the blocks alone would not know those rows).
      const double ndei = fit.model.Ndei(SliceSeries(train, 600, 1000), false);
      EXPECT_LT(ndei, 0.1);
      EXPECT_TRUE(std::isfinite(fit.model.Ndei(testing::NarendraValidate(500), true)));
    }
  }
  EXPECT_EQ(models[0], models[1]);
}

// The rule base is grown on the blocks the choice was made on, so the final model keeps the size
// that was chosen instead of growing with the record (the entropy test keeps finding novel
// tails in a longer one).
TEST(SearchSubsample, TheFinalModelKeepsTheRuleBaseGrownOnTheBlocks) {
  const Series train = testing::NarendraTrain(6000);
  const OfflineFitOptions o = SmallSearch();
  const OfflineFit fit =
      FitOffline(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, o);
  NarxModel grown(testing::NarendraSpec(), fit.config);
  grown.FitScaling(train);
  TrainOptions one;
  one.fit_scaling = false;
  Train(grown, SubsampleForSearch(train, o.search_budget), one);
  ASSERT_GT(fit.model.total_rules(), 1) << "the fuzzy setting is chosen on this plant";
  EXPECT_EQ(fit.model.total_rules(), grown.total_rules());
  // Searching every row instead is still possible (budget 0), and sees all of them.
  OfflineFitOptions whole = o;
  whole.search_budget.rows = 0;
  const OfflineFit all =
      FitOffline(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, whole);
  EXPECT_EQ(all.searched_rows, 6000);
}

}  // namespace
}  // namespace odonata::sysid

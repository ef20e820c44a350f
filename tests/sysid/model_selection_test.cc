// Model selection on a hold-out slice of the training data (docs/identifier.md §9).

#include <gtest/gtest.h>

#include "fuzzy/entropy_rule_generator.hpp"
#include "narendra_series.hpp"
#include "sysid/model_selection.hpp"

namespace odonata::sysid {
namespace {

TEST(ModelSelection, ThresholdGridMeansRadiiAndStaysInRange) {
  const auto t = DefaultThresholds();
  ASSERT_GE(t.size(), 5u);
  for (std::size_t k = 0; k < t.size(); ++k) {
    EXPECT_GT(t[k], 0.0);
    EXPECT_LT(t[k], fuzzy::kMaxRuleEntropy);
    if (k > 0) {
      EXPECT_GT(t[k], t[k - 1]) << "smaller radii need a higher H̄";
    }
  }
  // Radius 0 is a sample on a rule's centre: the largest entropy there is.
  EXPECT_NEAR(ThresholdForRadius(0.0), fuzzy::kMaxRuleEntropy, 1e-12);
}

TEST(ModelSelection, PicksTheFewestRulesWithinTheRelativeTolerance) {
  fuzzy::FuzzyModelConfig cfg;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(2.0), ThresholdForRadius(1.1), ThresholdForRadius(0.7)};
  o.kappas = {0.5, 1.0};
  o.max_epochs = 10;
  o.relative_tolerance = 0.10;
  const Series train = testing::NarendraTrain(1500);
  const SelectionResult r = SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, train, o);
  ASSERT_EQ(r.candidates.size(), 6u);
  EXPECT_EQ(r.holdout_samples, 300);
  EXPECT_EQ(r.fit_samples, 1200);
  EXPECT_TRUE(r.free_run_criterion) << "a model with output lags is chosen by simulation";
  const auto& best = r.candidates[r.best];
  const auto& chosen = r.candidates[r.chosen];
  for (const auto& c : r.candidates) {
    EXPECT_GE(c.score, best.score);
    EXPECT_EQ(c.score, c.holdout_free_run_ndei);
    EXPECT_GE(c.epochs, 1);
    EXPECT_LE(c.epochs, 10);
    if (c.score <= std::max(best.score * 1.10, best.score + o.absolute_tolerance)) {
      EXPECT_GE(c.rules, chosen.rules);
    }
  }
  EXPECT_LE(chosen.score, std::max(best.score * 1.10, best.score + o.absolute_tolerance));
  EXPECT_LT(best.score, 0.2) << "Narendra is learnable from 1200 samples";
}

TEST(ModelSelection, CandidatesLearnWithTheDeclaredScaling) {
  // Declaring the scaling the fitting slice would give itself must change nothing; ignoring the
  // declaration (identity scaling on raw Narendra data) would change every score.
  fuzzy::FuzzyModelConfig cfg;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.1)};
  o.kappas = {0.5, 1.0};
  o.max_epochs = 3;
  const Series train = testing::NarendraTrain(1000);
  const SelectionResult fitted =
      SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, train, o);
  NarxModel probe(testing::NarendraSpec(), cfg);
  probe.FitScaling(SliceSeries(train, 0, fitted.fit_samples));
  o.scaling = probe.scaling();
  const SelectionResult declared =
      SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, train, o);
  ASSERT_EQ(declared.candidates.size(), fitted.candidates.size());
  for (std::size_t k = 0; k < fitted.candidates.size(); ++k) {
    EXPECT_EQ(declared.candidates[k].score, fitted.candidates[k].score) << k;
    EXPECT_EQ(declared.candidates[k].rules, fitted.candidates[k].rules) << k;
  }
  Scaling wrong = probe.scaling();
  wrong.regressor_half *= 10.0;
  o.scaling = wrong;
  const SelectionResult off = SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, train, o);
  EXPECT_NE(off.candidates[0].score, fitted.candidates[0].score);
}

TEST(ModelSelection, OneStepCriterionForStaticMapsAndOnRequest) {
  fuzzy::FuzzyModelConfig cfg;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kSingleton};
  o.thresholds = {ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 3;
  o.criterion = SelectionCriterion::kOneStep;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, testing::NarendraTrain(600), o);
  ASSERT_EQ(r.candidates.size(), 1u);
  EXPECT_FALSE(r.free_run_criterion);
  EXPECT_EQ(r.candidates[0].score, r.candidates[0].holdout_one_step_ndei);
}

TEST(ModelSelection, WarnsAtTheGridsEdgeAndTheRuleCap) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.max_rules = 3;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.5), ThresholdForRadius(0.5)};
  o.kappas = {0.5};
  o.max_epochs = 2;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, testing::NarendraTrain(800), o);
  std::string all;
  for (const auto& w : r.warnings) all += w + "\n";
  EXPECT_NE(all.find("edge of its grid"), std::string::npos) << all;
  EXPECT_NE(all.find("rule cap"), std::string::npos) << all;
}

TEST(ModelSelection, RefusesATrainingSeriesTooShortToHoldOut) {
  SelectionOptions o;
  o.max_epochs = 1;
  EXPECT_THROW(SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{},
                           testing::NarendraTrain(8), o),
               std::invalid_argument);
}

}  // namespace
}  // namespace odonata::sysid

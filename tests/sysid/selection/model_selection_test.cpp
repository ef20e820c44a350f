// Model selection on a hold-out slice of the training data (docs/identifier.md §9).

#include <cmath>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "fuzzy/entropy_rule_generator.hpp"
#include "narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/offline_fit.hpp"

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

// The progress a fit's bar shows: one report per trained candidate at least, never going back,
// ending at the whole (the ridge variants, the short list and the folds counted in).
TEST(ModelSelection, ReportsProgressThatOnlyGrowsAndEndsWhole) {
  SelectionOptions o;
  o.thresholds = {ThresholdForRadius(2.0), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 5;
  o.simulation = {{20, 3}};
  std::vector<double> fractions;
  const SelectionResult r = SelectModel(
      testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{},
      testing::NarendraTrain(1200), o,
      [&](const Candidate&, const SelectionProgress& p) { fractions.push_back(p.fraction); });
  ASSERT_GE(fractions.size(), 5u) << "the linear model and the 2 x 2 grid at least";
  for (std::size_t k = 1; k < fractions.size(); ++k) EXPECT_GE(fractions[k], fractions[k - 1]);
  EXPECT_GT(fractions.front(), 0.0);
  EXPECT_EQ(fractions.back(), 1.0);
  EXPECT_LT(fractions[fractions.size() - 2], 1.0) << "the later steps had their share";
  EXPECT_GE(r.candidates.size(), 5u);
}

// The bar's whole-fit estimate is the leading candidate's cost: the last report leads with the
// candidate the selection chose, its training measured.
TEST(ModelSelection, ReportsTheLeadingCandidateItEndsOnWithItsCost) {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(2.0), ThresholdForRadius(1.1), ThresholdForRadius(0.7)};
  o.kappas = {1.0};
  o.max_epochs = 5;
  o.criterion = SelectionCriterion::kOneStep;
  o.deviation_ridges.clear();
  o.linear_check_folds = 0;
  std::vector<SelectionProgress> reports;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{},
                  testing::NarendraTrain(1200), o,
                  [&](const Candidate&, const SelectionProgress& p) { reports.push_back(p); });
  ASSERT_FALSE(reports.empty());
  const Candidate& chosen = r.candidates[r.chosen];
  const Candidate& leading = reports.back().leading;
  EXPECT_EQ(leading.linear, chosen.linear);
  EXPECT_EQ(leading.threshold, chosen.threshold);
  EXPECT_EQ(leading.rules, chosen.rules);
  EXPECT_EQ(leading.score, chosen.score);
  EXPECT_EQ(reports.back().fit_rows, r.fit_samples);
  EXPECT_GT(leading.cost.epochs_run, 0);
  EXPECT_GT(leading.cost.epochs_seconds, 0.0);
  for (const Candidate& c : r.candidates) EXPECT_GT(c.cost.epochs_run, 0);
}

// FitOffline tells the bar what its final training will take, during the selection and before
// the training starts, from the chosen candidate's cost on the rows it trains on.
TEST(FinalTrainingEstimate, ReachesTheProgressAndTheTrainingsStart) {
  OfflineFitOptions fo;
  fo.selection.consequents = {fuzzy::ConsequentKind::kLinear};
  fo.selection.thresholds = {ThresholdForRadius(2.0), ThresholdForRadius(1.1)};
  fo.selection.kappas = {1.0};
  fo.selection.max_epochs = 4;
  fo.selection.simulation.clear();
  fo.selection.deviation_ridges.clear();
  fo.selection.linear_check_folds = 0;
  std::vector<FinalTrainingEstimate> started;
  fo.on_training = [&](const FinalTrainingEstimate& e) { started.push_back(e); };
  double last_final_s = -1.0;
  const Series train = testing::NarendraTrain(1200);
  const OfflineFit fit = FitOffline(
      testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, fo,
      [&](const Candidate&, const SelectionProgress& p) { last_final_s = p.final_seconds; });
  ASSERT_TRUE(fit.selection);
  ASSERT_EQ(started.size(), 1u);
  EXPECT_EQ(started[0].epochs, fit.train.epochs);
  EXPECT_GT(started[0].epochs_seconds, 0.0);
  EXPECT_EQ(started[0].simulation_seconds, 0.0) << "no simulation stage was chosen";
  EXPECT_GT(last_final_s, 0.0);
}

// The final training's time from its candidate's: per epoch and per simulation step, times the
// final's epochs and steps, times the rows.
TEST(FinalTrainingEstimate, ScalesTheCandidatesCostToTheFinalTraining) {
  Candidate c;
  c.cost = TrainingCost{10, 2.0, 20, 4.0};
  c.simulation = {{10, 5}, {40, 5}};
  const FinalTrainingEstimate e = EstimateFinalTraining(c, 1000, 3000, 5);
  EXPECT_EQ(e.epochs, 5);
  EXPECT_DOUBLE_EQ(e.epochs_seconds, 2.0 / 10 * 5 * 3);
  EXPECT_DOUBLE_EQ(e.simulation_seconds, 4.0 / 20 * 10 * 3);
  const FinalTrainingEstimate unknown = EstimateFinalTraining(Candidate{}, 1000, 3000, 5);
  EXPECT_EQ(unknown.epochs_seconds, 0.0);
  EXPECT_EQ(unknown.simulation_seconds, 0.0);
  EXPECT_EQ(EstimateFinalTraining(c, 0, 3000, 5).epochs_seconds, 0.0);
}

TEST(ModelSelection, PicksTheFewestRulesWithinTheRelativeTolerance) {
  fuzzy::FuzzyModelConfig cfg;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(2.0), ThresholdForRadius(1.1), ThresholdForRadius(0.7)};
  o.kappas = {0.5, 1.0};
  o.max_epochs = 10;
  o.relative_tolerance = 0.10;
  o.deviation_ridges.clear();
  const Series train = testing::NarendraTrain(1500);
  const SelectionResult r = SelectModel(testing::NarendraSpec(), cfg, TrainOptions{}, train, o);
  ASSERT_EQ(r.candidates.size(), 7u);  // the linear model (one rule) and the 3 × 2 grid
  EXPECT_TRUE(r.candidates[0].linear);
  EXPECT_EQ(r.candidates[0].rules, 1);
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

// A candidate that grew to the rule cap has reached it even when its unsupported rules are then
// removed: the higher H̄ of its sweep would grow to the cap too and are skipped.
TEST(ModelSelection, ACandidateGrownToTheCapEndsItsSweepWhateverPruningLeaves) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.max_rules = 3;
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.5), ThresholdForRadius(0.7), ThresholdForRadius(0.5)};
  o.kappas = {0.5};
  o.max_epochs = 2;
  o.deviation_ridges.clear();
  TrainOptions t;
  t.min_rule_support = 1e6;  // every rule but the best-supported one goes
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), cfg, t, testing::NarendraTrain(800), o);
  ASSERT_EQ(r.candidates.size(), 2u);  // ARX and the first H̄; the other two were skipped
  EXPECT_EQ(r.candidates[1].rules, 1);
  EXPECT_TRUE(r.candidates[1].at_cap);
}

// y(k+1) = 0.8 y(k) + 0.3 u(k) (+ a Gaussian disturbance of `disturbance_sd` inside the plant),
// measured with Gaussian noise of `noise_sd`; u steps every 8 samples. A zero σ draws nothing.
Series NoisyFirstOrder(int samples, unsigned seed, double noise_sd, double disturbance_sd = 0.0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  Series s;
  s.inputs.resize(samples, 1);
  s.outputs.resize(samples, 1);
  double y = 0, u = 0;
  for (int k = 0; k < samples; ++k) {
    if (k % 8 == 0) u = level(rng);
    s.inputs(k, 0) = u;
    s.outputs(k, 0) = noise_sd > 0 ? y + noise_sd * gauss(rng) : y;
    y = 0.8 * y + 0.3 * u + (disturbance_sd > 0 ? disturbance_sd * gauss(rng) : 0.0);
  }
  return s;
}

// 1600 samples of a damped second-order plant under held random steps, output noise σ 0.2;
// `nonlinear`: its input through tanh(1.5 u).
Series NoisySecondOrder(unsigned seed, bool nonlinear) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> noise(0.0, 0.2);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  Series s;
  s.inputs.resize(1600, 1);
  s.outputs.resize(1600, 1);
  double x1 = 0, x2 = 0, u = 0;
  for (int k = 0; k < 1600; ++k) {
    if (k % 10 == 0) u = level(rng);
    s.inputs(k, 0) = u;
    s.outputs(k, 0) = x1 + noise(rng);
    const double next = 0.85 * x1 - 0.1 * x2 + 0.3 * (nonlinear ? std::tanh(1.5 * u) : u);
    x2 = x1;
    x1 = next;
  }
  return s;
}

// A linear plant with output noise: no rule beyond the first is worth its parameters, so the
// linear model is chosen — by the hold-out or by the cross-validation that a fuzzy winner of one
// tail slice must also pass.
TEST(ModelSelection, TheLinearModelIsChosenWhenTheFuzzyOneDoesNotBeatIt) {
  const Series s = NoisyFirstOrder(1200, 3, 0.05);
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.kappas = {1.0};
  o.max_epochs = 5;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  const Candidate& c = r.candidates[r.chosen];
  EXPECT_TRUE(c.linear);
  EXPECT_EQ(c.rules, 1);
  const fuzzy::FuzzyModelConfig cfg = CandidateConfig(fuzzy::FuzzyModelConfig{}, c);
  EXPECT_EQ(cfg.entropy.max_rules, 1);
  ASSERT_TRUE(r.chosen_model.has_value()) << "the fallback model is the one chosen: ARX";
  EXPECT_EQ(r.chosen_model->total_rules(), 1);
}

// The standard error of paired fold differences: differences 1, 2, 3, 4 have a sample deviation
// of 1.29, so 0.645 over four folds; a diverged fold or a single fold leaves the means alone.
TEST(ModelSelection, PairedStandardErrorOfFoldDifferences) {
  EXPECT_NEAR(PairedStandardError({1, 2, 3, 4}, {2, 4, 6, 8}), std::sqrt(5.0 / 3.0 / 4.0), 1e-15);
  EXPECT_EQ(PairedStandardError({1, 2, 3}, {2, 3, 4}), 0.0) << "equal differences";
  EXPECT_EQ(PairedStandardError({1, std::numeric_limits<double>::infinity()}, {1, 2}), 0.0);
  EXPECT_EQ(PairedStandardError({1}, {2}), 0.0);
}

// A linear plant under noise: where a fuzzy candidate wins the hold-out by chance, it loses the
// folds, and so do the next ones by hold-out score, each against the same linear folds and by a
// margin that grows with the folds' spread; ARX is chosen. With one candidate allowed, the
// hold-out's choice alone faces them.
TEST(ModelSelection, WhenTheChoiceLosesTheFoldsTheNextByHoldOutScoreFaceThem) {
  // 400 samples, noise a third of the output's deviation: seed 1 is such a chance.
  const Series s = NoisyFirstOrder(400, 1, 0.1);
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.kappas = {1.0};
  o.max_epochs = 3;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  EXPECT_TRUE(r.candidates[r.chosen].linear);
  ASSERT_EQ(r.linear_checks.size(), static_cast<std::size_t>(o.linear_check_candidates));
  for (std::size_t i = 0; i < r.linear_checks.size(); ++i) {
    const LinearCheck& lc = r.linear_checks[i];
    EXPECT_TRUE(lc.done && lc.linear_chosen) << "check " << i;
    EXPECT_FALSE(r.candidates[lc.candidate].linear);
    EXPECT_EQ(lc.linear_folds, r.linear_checks.front().linear_folds);
    for (std::size_t j = 0; j < i; ++j) EXPECT_NE(lc.candidate, r.linear_checks[j].candidate);
    if (i >= 2) {
      EXPECT_GE(r.candidates[lc.candidate].score,
                r.candidates[r.linear_checks[i - 1].candidate].score);
    }
  }
  EXPECT_EQ(r.linear_check.candidate, r.linear_checks.front().candidate);
  // The hold-out's choice needs the absolute tolerance; a second look, also the standard error
  // of the folds' paired differences (the one-standard-error rule).
  EXPECT_EQ(r.linear_checks.front().margin, o.absolute_tolerance);
  bool error_decides = false;
  for (std::size_t i = 1; i < r.linear_checks.size(); ++i) {
    const LinearCheck& lc = r.linear_checks[i];
    const std::size_t k = lc.fuzzy_folds.size();
    Eigen::ArrayXd d(static_cast<Eigen::Index>(k));
    for (std::size_t f = 0; f < k; ++f)
      d(static_cast<Eigen::Index>(f)) = lc.linear_folds[f] - lc.fuzzy_folds[f];
    const double se = std::sqrt((d - d.mean()).square().sum() / double(k - 1) / double(k));
    EXPECT_NEAR(lc.margin, std::max(o.absolute_tolerance, se), 1e-12) << "check " << i;
    EXPECT_EQ(lc.linear_chosen, !(lc.fuzzy_score + lc.margin < lc.linear_score));
    error_decides = error_decides || se > o.absolute_tolerance;
  }
  EXPECT_TRUE(error_decides) << "the folds of this record vary by more than the tolerance";
  ASSERT_TRUE(r.chosen_model.has_value());
  EXPECT_EQ(r.chosen_model->total_rules(), 1);

  o.linear_check_candidates = 1;
  const SelectionResult one =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  ASSERT_EQ(one.linear_checks.size(), 1u);
  EXPECT_EQ(one.linear_checks.front().candidate, r.linear_checks.front().candidate);
  EXPECT_TRUE(one.candidates[one.chosen].linear);
}

// The series with its last 320 samples (the selection's 20 % hold-out of 1600) offset by a drift
// growing to 0.3: a hold-out slice unlike the rest.
Series DriftingAtTheEnd(Series s) {
  for (Eigen::Index k = 1280; k < 1600; ++k) s.outputs(k, 0) += 0.3 * double(k - 1280) / 320.0;
  return s;
}

// Linear consequents, two thresholds (so the linear model is a candidate), a short schedule.
SelectionOptions LinearFitCheckOptions() {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 3;
  o.simulation = {{10, 10}, {40, 10}};
  return o;
}

// A linear plant whose output is measured with noise: least squares on the noisy lags is
// biased, the output-error fit of the linear model is not, and the folds keep it. With a K-step
// criterion the linear model keeps its one-step fit (no such check).
TEST(ModelSelection, TheFoldsKeepTheLinearModelsOutputErrorFitWhenItWins) {
  const Series s = NoisySecondOrder(7, false);
  SelectionOptions o = LinearFitCheckOptions();
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  ASSERT_TRUE(r.output_error_check.done);
  EXPECT_TRUE(r.output_error_linear) << "output error " << r.output_error_check.fuzzy_score
                                     << ", one step " << r.output_error_check.linear_score;
  EXPECT_LT(r.output_error_check.fuzzy_score, r.output_error_check.linear_score);
  const Candidate& linear = r.candidates.front();
  ASSERT_TRUE(linear.linear);
  ASSERT_FALSE(linear.simulation.empty());
  EXPECT_TRUE(linear.simulation.back().gauss_newton);
  EXPECT_EQ(linear.simulation.back().horizon, 40) << "the longest window of the schedule";

  o.horizon = 5;
  const SelectionResult ahead =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  EXPECT_FALSE(ahead.output_error_check.done);
  for (const auto& st : ahead.candidates.front().simulation) EXPECT_FALSE(st.gauss_newton);
}

// The linear model's output-error fit is its optimum on the fit slice, whatever step the hold-out
// slice would have preferred: five parameters do not overfit hundreds of samples, and a slice
// that drifts (here its output slowly offset by up to 0.3; the tanks' last 100 training rows,
// after an overflow) stopped it 2.7 % of its loss short of it (docs/identifier.md §12).
TEST(ModelSelection, TheLinearModelsOutputErrorFitIsItsOptimumNotTheHoldOutsBestStep) {
  const Series s = DriftingAtTheEnd(NoisySecondOrder(5, false));
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, s, LinearFitCheckOptions());
  ASSERT_EQ(r.holdout_samples, 320) << "the drift is the hold-out";
  ASSERT_TRUE(r.output_error_linear);
  ASSERT_TRUE(r.candidates[r.chosen].linear) << "a linear plant";
  ASSERT_TRUE(r.chosen_model.has_value());
  const Series fit = SliceSeries(s, 0, r.fit_samples);
  // Its own schedule once more, from where it ended.
  SimulationTrainOptions more;
  more.stages = r.candidates[r.chosen].simulation;
  ASSERT_EQ(more.stages.size(), 1u);
  const int horizon = more.stages.front().horizon;
  NarxModel further = *r.chosen_model;
  TrainOnSimulationError(further, fit, more);
  const double at = SimulationLoss(*r.chosen_model, fit, horizon);
  EXPECT_NEAR(SimulationLoss(further, fit, horizon), at, 1e-6 * at) << "more iterations gain";
}

// Noise that enters the plant itself (an equation error): least squares is the linear model's
// right fit, and its output-error fit does not win the folds. The linear model is then least
// squares exactly, ARX, with no simulation step of its own: the schedule that the final fit
// replays on the whole file is empty, so no step that a short hold-out kept can take it away
// from both fits (docs/identifier.md §12).
TEST(ModelSelection, WhenItsOutputErrorFitLosesTheLinearModelIsLeastSquaresExactly) {
  const Series s = NoisyFirstOrder(1200, 1, 0.0, 0.1);
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, s, LinearFitCheckOptions());
  ASSERT_TRUE(r.output_error_check.done) << "the folds compare both fits";
  EXPECT_FALSE(r.output_error_linear) << "output error " << r.output_error_check.fuzzy_score
                                      << ", one step " << r.output_error_check.linear_score;
  const Candidate& linear = r.candidates.front();
  ASSERT_TRUE(linear.linear);
  EXPECT_TRUE(linear.simulation.empty()) << linear.simulation.size() << " stages kept";
}

// Narendra's plant is far from linear: the fuzzy model wins the hold-out and the blocked
// cross-validation alike, fold by fold.
TEST(ModelSelection, ANonlinearPlantKeepsItsFuzzyModelThroughCrossValidation) {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 10;
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, testing::NarendraTrain(1500), o);
  EXPECT_FALSE(r.candidates[r.chosen].linear);
  ASSERT_TRUE(r.linear_check.done);
  ASSERT_EQ(r.linear_checks.size(), 1u) << "the hold-out's choice won: no other is checked";
  EXPECT_EQ(r.linear_check.candidate, r.chosen);
  ASSERT_EQ(r.linear_check.fuzzy_folds.size(), 4u);
  EXPECT_FALSE(r.linear_check.linear_chosen);
  for (std::size_t f = 0; f < 4; ++f)
    EXPECT_LT(r.linear_check.fuzzy_folds[f], r.linear_check.linear_folds[f]) << "fold " << f;
  // The model kept beside the choice is the one the hold-out judged, bit for bit: FitOffline
  // falls back on it when the setting trained on every row runs away at rest.
  const Candidate& c = r.candidates[r.chosen];
  ASSERT_TRUE(r.chosen_model.has_value());
  EXPECT_EQ(r.chosen_model->total_rules(), c.rules);
  const Series train = testing::NarendraTrain(1500);
  const Series holdout = SliceSeries(train, r.fit_samples, r.holdout_samples);
  EXPECT_EQ(r.chosen_model->Ndei(holdout, true), c.score);
}

// The best fuzzy candidates are trained again shrunk toward the global linear model, each ridge
// a candidate of its own. A huge ridge gives every rule the global least-squares consequent:
// whatever its premises, that model predicts as the linear one (ARX) does.
TEST(ModelSelection, TheBestFuzzyCandidatesAreAlsoTriedShrunkTowardTheLinearModel) {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 4;
  o.deviation_ridges = {0.1, 1e9};
  o.ridge_shortlist = 1;
  o.linear_check_folds = 0;
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, testing::NarendraTrain(900), o);
  ASSERT_EQ(r.candidates.size(), 5u);  // ARX, the two H̄, and the best one with two ridges
  const Candidate& linear = r.candidates[0];
  ASSERT_TRUE(linear.linear);
  std::size_t best_plain = 1;
  for (std::size_t k = 1; k < 3; ++k) {
    EXPECT_EQ(r.candidates[k].deviation_ridge, 0.0);
    if (r.candidates[k].score < r.candidates[best_plain].score) best_plain = k;
  }
  const Candidate& mild = r.candidates[3];
  const Candidate& huge = r.candidates[4];
  for (const Candidate* c : {&mild, &huge}) {
    EXPECT_EQ(c->threshold, r.candidates[best_plain].threshold);
    EXPECT_EQ(c->kappa, r.candidates[best_plain].kappa);
    EXPECT_FALSE(c->linear);
    EXPECT_TRUE(std::isfinite(c->score));
  }
  EXPECT_EQ(mild.deviation_ridge, 0.1);
  EXPECT_EQ(huge.deviation_ridge, 1e9);
  EXPECT_NE(mild.holdout_one_step_ndei, r.candidates[best_plain].holdout_one_step_ndei);
  EXPECT_NEAR(huge.holdout_one_step_ndei, linear.holdout_one_step_ndei,
              1e-4 * linear.holdout_one_step_ndei);
  EXPECT_GT(huge.rules, 1);
}

// With a horizon the candidates are scored K steps ahead, and that is the criterion.
TEST(ModelSelection, AHorizonScoresAndChoosesKStepsAhead) {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 3;
  o.horizon = 5;
  o.linear_check_folds = 0;
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, testing::NarendraTrain(800), o);
  EXPECT_EQ(r.criterion_horizon, 5);
  EXPECT_FALSE(r.free_run_criterion);
  for (const auto& c : r.candidates) {
    EXPECT_EQ(c.score, c.holdout_ahead_ndei);
    EXPECT_TRUE(std::isfinite(c.holdout_ahead_ndei));
  }
  o.criterion = SelectionCriterion::kAhead;
  o.horizon = 0;
  EXPECT_THROW(SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{},
                           testing::NarendraTrain(800), o),
               std::invalid_argument);
}

// Scored K steps ahead, no candidate may be worse one step ahead than the linear model (one-step
// least squares) by more than the margin: on a noisy linear plant, with no margin, the rule bases
// that fit the noise lose to it one step ahead and are out. In free run there is no such bound.
TEST(ModelSelection, KStepsAheadNoCandidateLosesToTheLinearModelOneStepAhead) {
  const Series s = NoisySecondOrder(5, false);
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1), ThresholdForRadius(0.7)};
  o.kappas = {1.0};
  o.max_epochs = 3;
  o.linear_check_folds = 0;
  o.relative_tolerance = 0.0;
  o.absolute_tolerance = 0.0;
  for (const int horizon : {10, 20}) {
    o.horizon = horizon;
    const SelectionResult r =
        SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
    ASSERT_EQ(r.criterion_horizon, horizon);
    const Candidate& linear = r.candidates.front();
    ASSERT_TRUE(linear.linear);
    EXPECT_EQ(r.one_step_bound, linear.holdout_one_step_ndei) << horizon;
    int lost = 0;
    for (const Candidate& c : r.candidates) {
      if (c.linear) continue;
      if (c.one_step_lost) {
        ++lost;
        EXPECT_GT(c.holdout_one_step_ndei, r.one_step_bound) << horizon;
        EXPECT_EQ(c.score, std::numeric_limits<double>::infinity()) << horizon;
      } else {
        EXPECT_LE(c.holdout_one_step_ndei, r.one_step_bound) << horizon;
        EXPECT_EQ(c.score, c.holdout_ahead_ndei) << horizon;
      }
    }
    EXPECT_GT(lost, 0) << horizon << ": a rule base fitted to the noise is worse one step ahead";
    EXPECT_LE(r.candidates[r.chosen].holdout_one_step_ndei, r.one_step_bound) << horizon;
  }
  o.horizon = 0;
  const SelectionResult free_run =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  ASSERT_EQ(free_run.criterion_horizon, 0);
  EXPECT_EQ(free_run.one_step_bound, std::numeric_limits<double>::infinity());
  for (const Candidate& c : free_run.candidates) EXPECT_FALSE(c.one_step_lost);
  // One step ahead the score is the one-step NDEI itself.
  o.criterion = SelectionCriterion::kOneStep;
  EXPECT_EQ(SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o)
                .one_step_bound,
            std::numeric_limits<double>::infinity());
}

// The short list takes simulation-error training; the schedule each kept is recorded, so the
// final fit can repeat it, and a trained candidate's hold-out score is never worse than before.
TEST(ModelSelection, TheShortListTrainsOnTheSimulationError) {
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 5;
  o.linear_check_folds = 0;
  const Series train = testing::NarendraTrain(1000);
  const SelectionResult plain =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, o);
  o.simulation = {{10, 10}, {40, 10}};
  o.simulation_shortlist = 1;
  const SelectionResult trained =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, o);
  // The same candidates, then the short list's fuzzy one again from the linear model's fit (when
  // its hold-out kept a step of it).
  ASSERT_GE(trained.candidates.size(), plain.candidates.size());
  ASSERT_LE(trained.candidates.size(), plain.candidates.size() + 1);
  int shortlisted = 0;
  for (std::size_t k = 0; k < plain.candidates.size(); ++k) {
    EXPECT_LE(trained.candidates[k].score, plain.candidates[k].score);
    if (!trained.candidates[k].simulation.empty()) ++shortlisted;
    for (const auto& st : trained.candidates[k].simulation) {
      EXPECT_FALSE(st.from_linear);
      // The schedule's stages; then, free run reported, Levenberg–Marquardt on the longest.
      EXPECT_LE(st.steps, st.gauss_newton ? 50 : 10);
      if (st.gauss_newton) {
        EXPECT_EQ(st.horizon, 40);
      }
    }
  }
  EXPECT_LE(shortlisted, 2);  // the linear model and the best fuzzy one, when either improved
  for (std::size_t k = plain.candidates.size(); k < trained.candidates.size(); ++k) {
    const Candidate& c = trained.candidates[k];
    ASSERT_FALSE(c.simulation.empty());
    EXPECT_TRUE(c.simulation.front().from_linear && c.simulation.front().gauss_newton);
    EXPECT_FALSE(c.linear);
    EXPECT_EQ(c.consequent, fuzzy::ConsequentKind::kLinear);
    EXPECT_GT(c.rules, 1);
  }
}

// Output noise on a mildly nonlinear plant: the short list's fuzzy candidates are also trained
// from the linear model's output-error fit, and those the hold-out kept a step of are candidates
// of their own, scored on the hold-out like the rest; off, there are none.
TEST(ModelSelection, TheShortListAlsoRestartsFromTheLinearModelsFit) {
  const Series s = NoisySecondOrder(11, true);
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 3;
  o.simulation = {{10, 10}, {40, 10}};
  o.linear_check_folds = 0;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  int restarts = 0;
  for (const Candidate& c : r.candidates) {
    if (c.simulation.empty() || !c.simulation.front().from_linear) continue;
    ++restarts;
    EXPECT_FALSE(c.linear);
    EXPECT_GT(c.rules, 1);
    EXPECT_TRUE(std::isfinite(c.score));
    EXPECT_EQ(c.simulation.front().horizon, 40) << "the longest window of the schedule";
  }
  EXPECT_GE(restarts, 1);
  o.restart_from_linear = false;
  const SelectionResult off =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  EXPECT_EQ(off.candidates.size() + static_cast<std::size_t>(restarts), r.candidates.size());
  for (const Candidate& c : off.candidates)
    for (const auto& st : c.simulation) EXPECT_FALSE(st.from_linear);
}

// Kept for one epoch, a setting's ridge variants share its premises, and a restart from the
// linear model's fit sets every consequent: their restarts would be one model listed, trained and
// cross-validated as several. One restart is made of it.
TEST(ModelSelection, RestartsFromTheSamePremisesAreOneCandidate) {
  const Series s = NoisySecondOrder(11, true);
  SelectionOptions o;
  o.consequents = {fuzzy::ConsequentKind::kLinear};
  o.thresholds = {ThresholdForRadius(1.1)};
  o.kappas = {1.0};
  o.max_epochs = 1;
  o.deviation_ridges = {0.01, 0.1, 1.0};
  o.ridge_shortlist = 1;
  o.simulation = {{10, 10}, {40, 10}};
  o.simulation_shortlist = 3;
  o.linear_check_folds = 0;
  const SelectionResult r =
      SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, s, o);
  // ARX, the setting and its three ridge variants, of which the short list takes three.
  int fuzzy = 0;
  std::vector<const Candidate*> restarts;
  for (const Candidate& c : r.candidates) {
    if (c.linear) continue;
    if (!c.simulation.empty() && c.simulation.front().from_linear)
      restarts.push_back(&c);
    else
      ++fuzzy;
  }
  ASSERT_EQ(fuzzy, 4);
  ASSERT_EQ(restarts.size(), 1u);
  EXPECT_TRUE(std::isfinite(restarts.front()->score));

  // The check itself: the same training gives the same premises; another H̄ another rule base.
  const auto trained = [&](double threshold) {
    Candidate c;
    c.threshold = threshold;
    c.kappa = 1.0;
    NarxModel m(testing::NarendraSpec(), CandidateConfig(fuzzy::FuzzyModelConfig{}, c));
    Train(m, s, TrainOptions{});
    return m;
  };
  const NarxModel a = trained(ThresholdForRadius(1.1));
  EXPECT_TRUE(SamePremises(a, trained(ThresholdForRadius(1.1))));
  EXPECT_TRUE(SamePremises(a, a));
  const NarxModel b = trained(ThresholdForRadius(0.6));
  ASSERT_NE(a.total_rules(), b.total_rules());
  EXPECT_FALSE(SamePremises(a, b));
}

// When the folds keep the linear model, the warning names the fit that is kept: here (a linear
// plant whose hold-out drifts, so a fuzzy candidate wins that slice and loses the folds) the
// output-error fit, not ARX.
TEST(ModelSelection, TheFoldsWarningNamesTheLinearFitKept) {
  const Series s = DriftingAtTheEnd(NoisySecondOrder(2, false));
  const SelectionResult r = SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{},
                                        TrainOptions{}, s, LinearFitCheckOptions());
  ASSERT_FALSE(r.linear_checks.empty()) << "a fuzzy candidate faced the folds";
  ASSERT_TRUE(r.candidates[r.chosen].linear);
  ASSERT_TRUE(r.output_error_linear);
  int named = 0;
  for (const std::string& w : r.warnings) {
    if (w.find("is chosen") == std::string::npos) continue;
    ++named;
    EXPECT_NE(w.find("the linear model (its output-error fit) is chosen"), std::string::npos) << w;
  }
  EXPECT_EQ(named, 1);
}

TEST(ModelSelection, ConcatenatedSeriesBreakAtTheSeam) {
  const Series a = testing::NarendraTrain(50), b = testing::NarendraTrain(40, 9);
  const Series c = ConcatSeries(a, b);
  EXPECT_EQ(c.samples(), 90);
  ASSERT_EQ(c.breaks.size(), 1u);
  EXPECT_EQ(c.breaks[0], 50);
  EXPECT_EQ(c.outputs(50, 0), b.outputs(0, 0));
  // No regressor reads across the seam: the second part's targets start after its own lags.
  const auto t = TargetRows(testing::NarendraSpec(), c);
  for (const auto row : t)
    EXPECT_TRUE(row < 50 || row >= 50 + testing::NarendraSpec().first_target());
}

// The rest test: y(t) = 2r cos(ω) y(t−1) − r² y(t−2) held at zero input. Damped (r < 1) it comes
// to rest; undamped (r = 1) it oscillates by itself for ever, which no hold-out need show.
TEST(ModelSelection, RestDeviationTellsASelfExcitedModelFromOneThatSettles) {
  RegressorSpec spec;
  spec.outputs = {"y"};
  spec.inputs = {"u"};
  spec.output_lags = 2;
  spec.input_lags = 1;
  Series train;
  train.outputs = Eigen::VectorXd::LinSpaced(500, -1.0, 1.0);
  train.inputs = Eigen::VectorXd::Zero(500);
  auto model = [&](double r) {
    fuzzy::FuzzyModelConfig cfg;
    cfg.entropy.max_rules = 1;
    NarxModel m(spec, cfg);
    m.Learn(Eigen::Vector3d(0, 0, 0), Eigen::VectorXd::Zero(1));  // the one rule
    const double w = 0.3;
    Eigen::VectorXd theta(4);
    theta << 0.0, 2 * r * std::cos(w), -r * r, 0.0;  // a0, y(t−1), y(t−2), u(t−1)
    m.mutable_model(0).mutable_consequent().SetParameters(theta);
    return m;
  };
  EXPECT_LT(RestDeviation(model(0.9), train), 1e-6);
  EXPECT_GT(RestDeviation(model(1.0), train), 0.01);
  EXPECT_GT(RestDeviation(model(1.05), train), 1e3);  // unstable: it grows without bound
}

TEST(ModelSelection, RefusesATrainingSeriesTooShortToHoldOut) {
  SelectionOptions o;
  o.max_epochs = 1;
  EXPECT_THROW(SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{},
                           testing::NarendraTrain(8), o),
               std::invalid_argument);
}

// The rest check the candidates and the final model share: not at rest is a deviation above 1 %
// of the output's and above ten times the linear model's; a diverged run is never at rest.
TEST(ModelSelection, RestlessMeansMovingWhereTheLinearModelSettles) {
  EXPECT_FALSE(Restless(0.0, 0.0));
  EXPECT_FALSE(Restless(0.009, 0.0));
  EXPECT_TRUE(Restless(0.011, 0.0));
  EXPECT_TRUE(Restless(0.67, 1e-16));  // the Silverbox's limit cycle
  EXPECT_FALSE(Restless(0.05, 0.01));  // a linear model that itself moves sets the bar
  EXPECT_TRUE(Restless(0.2, 0.01));
  EXPECT_TRUE(Restless(std::numeric_limits<double>::infinity(), 0.0));
  EXPECT_TRUE(Restless(std::numeric_limits<double>::quiet_NaN(), 0.0));
}

}  // namespace
}  // namespace odonata::sysid

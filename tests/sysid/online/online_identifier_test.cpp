#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "metrics/conformal.hpp"
#include "narendra_series.hpp"
#include "online_fixtures.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/narx_model_state.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/online/refit_judgements.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {
namespace {

using testing::Empty;
using testing::Row;

TEST(OnlineIdentifier, ReproducesTheOfflineTrainerBitForBit) {
  const Series train = testing::NarendraTrain(1500);
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    NarxModel offline = Empty(kind, train);
    TrainOptions o;
    o.refine_least_squares = false;
    o.fit_scaling = false;
    Train(offline, train, o);
    OnlineIdentifier online(Empty(kind, train));
    for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(train, k));
    EXPECT_EQ(online.model().ToJson().dump(), offline.ToJson().dump()) << ToString(kind);
    EXPECT_EQ(online.samples_learned(), train.samples() - 1);
  }
}

TEST(RefitSchedule, DoublesThenKeepsItsPace) {
  RefitSchedule doubling;
  doubling.first = 100;
  for (int64_t n : {100, 200, 400, 800, 1600}) EXPECT_TRUE(doubling.Due(n)) << n;
  for (int64_t n : {1, 99, 101, 300, 1000}) EXPECT_FALSE(doubling.Due(n)) << n;
  RefitSchedule paced = doubling;
  paced.every = 500;
  for (int64_t n : {100, 200, 400, 500, 1000, 1500}) EXPECT_TRUE(paced.Due(n)) << n;
  for (int64_t n : {300, 800, 1200, 1600}) EXPECT_FALSE(paced.Due(n)) << n;
  EXPECT_FALSE(RefitSchedule{}.Due(100)) << "off by default";
}

// The fit options of the refit that closes learning: odonata-fit's defaults on the samples kept,
// scaling included (each candidate scaled to what it trains on), linear consequents as configured.
OfflineFitOptions ClosingRefitFitOptions() {
  OfflineFitOptions fo;
  fo.selection.simulation = DefaultSimulationStages();
  fo.selection.consequents = {fuzzy::ConsequentKind::kLinear};
  return fo;
}

// One learner, two schedules (docs/identifier.md §6.3): refits run odonata-fit's learner in a
// worker thread and land at fixed counts, so the result is the same whatever the threads do.
TEST(OnlineIdentifier, ScheduledRefitsAreDeterministicAndCloseWithOdonataFitsModel) {
  // Small enough that its five model selections stay well inside the timeout under the
  // sanitizers on one busy core (1200 samples took 177 s quiet there, over 300 s with two hogs).
  const Series train = testing::NarendraTrain(600);
  RefitSchedule refit;
  refit.first = 150;
  refit.every = 300;
  refit.buffer = 5000;  // holds the whole record: the closing refit sees every sample
  const NarxModel empty = Empty(fuzzy::ConsequentKind::kLinear, train);
  OnlineIdentifier online(empty, refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(train, k));
  // 150 lands at 300, where the next begins; the freeze at 599 replaces that one with the
  // closing refit on all 600 samples, which lands when the model is next used.
  EXPECT_EQ(online.refits(), 1);
  online.Freeze();
  EXPECT_EQ(online.refits(), 1) << "a freeze does not wait for the closing refit";
  online.Settle();
  EXPECT_EQ(online.refits(), 2);
  EXPECT_EQ(online.failed_refits(), 0);
  // The closing refit saw the whole record: the model is odonata-fit's on it, bit for bit.
  const OfflineFit offline = FitOffline(empty.spec(), empty.model(0).config(), TrainOptions{},
                                        train, ClosingRefitFitOptions());
  EXPECT_EQ(online.model().ToJson().dump(), offline.model.ToJson().dump());
  // odonata-fit's replay of the identifier is the same class, the same counts.
  const OnlineReplay replay =
      LearnOnline(Empty(fuzzy::ConsequentKind::kLinear, train), refit, train, empty.scaling());
  EXPECT_EQ(replay.model.ToJson().dump(), online.model().ToJson().dump());
  EXPECT_EQ(replay.refits, 2);
}

// A loop that integrates is reported K steps ahead, and odonata-fit --horizon K chooses by that:
// the identifier's refits (refit_horizon) choose as it does, not in free run.
TEST(OnlineIdentifier, RefitsWithAHorizonChooseAsOdonataFitDoesWithIt) {
  const Series train = testing::NarendraTrain(250);
  RefitSchedule refit;
  refit.first = 1000;  // only the freeze's closing refit, on every sample
  refit.buffer = 5000;
  refit.horizon = 3;
  const NarxModel empty = Empty(fuzzy::ConsequentKind::kLinear, train);
  OnlineIdentifier online(empty, refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(train, k));
  online.Freeze();
  online.Settle();
  ASSERT_EQ(online.refits(), 1);
  OfflineFitOptions fo = ClosingRefitFitOptions();
  const OfflineFit free_run =
      FitOffline(empty.spec(), empty.model(0).config(), TrainOptions{}, train, fo);
  fo.selection.horizon = refit.horizon;
  const OfflineFit ahead =
      FitOffline(empty.spec(), empty.model(0).config(), TrainOptions{}, train, fo);
  ASSERT_TRUE(ahead.selection.has_value());
  EXPECT_EQ(ahead.selection->criterion_horizon, refit.horizon);
  // On this record the two criteria train different models, so the comparison tells them apart.
  ASSERT_NE(ahead.model.ToJson().dump(), free_run.model.ToJson().dump());
  EXPECT_EQ(online.model().ToJson().dump(), ahead.model.ToJson().dump());
}

// A landed refit's model starts its live intervals from its own calibration, as odonata-fit
// calibrates its (issue 60): the chosen candidate's residuals on the selection's hold-out. Frozen
// after the closing refit, the widths are the conformal ranks of exactly those residuals, one step,
// K steps ahead and in free run.
TEST(OnlineIdentifier, ALandedRefitStartsItsIntervalsFromItsCalibrationResiduals) {
  const Series all = testing::NarendraTrain(260);
  const Series train = SliceSeries(all, 0, 250);
  RefitSchedule refit;
  refit.first = 1000;  // only the freeze's closing refit, on every sample
  refit.buffer = 5000;
  refit.horizon = 3;
  const NarxModel empty = Empty(fuzzy::ConsequentKind::kLinear, train);
  OnlineIdentifier online(empty, refit);
  online.set_ahead_horizon(3);
  for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(all, k));
  online.Freeze();
  const auto report = online.Push(Row(all, 250));  // the closing refit lands before it
  ASSERT_TRUE(report);
  ASSERT_EQ(online.refits(), 1);
  OfflineFitOptions fo = ClosingRefitFitOptions();
  fo.selection.horizon = refit.horizon;
  const OfflineFit offline =
      FitOffline(empty.spec(), empty.model(0).config(), TrainOptions{}, train, fo);
  ASSERT_TRUE(offline.selection && offline.selection->chosen_model);
  const Eigen::Index held = offline.selection->holdout_samples;
  const Series holdout = SliceSeries(train, train.samples() - held, held);
  const NarxModel& candidate = *offline.selection->chosen_model;
  auto modes = ModePredictions(
      empty.spec(), holdout, [&](const Eigen::VectorXd& x) { return candidate.Predict(x); }, 3);
  const Eigen::MatrixXd y = Targets(empty.spec(), holdout);
  const auto rank = [&](const Eigen::MatrixXd& yhat) {
    std::vector<double> e;
    for (Eigen::Index r = 0; r < y.rows(); ++r) e.push_back(std::abs(y(r, 0) - yhat(r, 0)));
    return metrics::ConformalHalfWidth(e, 0.9);
  };
  EXPECT_EQ(report->half_width(0), rank(modes["one_step"]));
  EXPECT_EQ(report->ahead_half_width(0), rank(modes["k_step"]));
  EXPECT_EQ(report->free_run_half_width(0), rank(modes["free_run"]));
  EXPECT_TRUE(std::isfinite(report->ahead_half_width(0)));
}

// A service whose landing waits for a refit cannot beat its heartbeat meanwhile: the hook is
// how it keeps saying "refitting" for as long as the wait lasts, so a lockstep generator that
// starts during a freeze's closing refit still counts it as a consumer (docs/lcm.md §10).
TEST(OnlineIdentifier, AWaitForARefitCallsTheWaitHookAgainEveryPeriod) {
  const Series train = testing::NarendraTrain(300);
  RefitSchedule refit;
  refit.first = 1000;  // no scheduled refit within the record: only the freeze's closing one
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  using Clock = std::chrono::steady_clock;
  constexpr auto kPeriod = std::chrono::milliseconds(2);
  std::vector<Clock::time_point> calls;
  std::vector<int64_t> refits_at_call;
  id.SetRefitWaitHook(
      [&] {
        calls.push_back(Clock::now());
        refits_at_call.push_back(id.refits());
        return RefitWait::kKeepWaiting;
      },
      kPeriod);
  for (Eigen::Index k = 0; k < train.samples(); ++k) id.Push(Row(train, k));
  ASSERT_TRUE(calls.empty()) << "nothing waited before the freeze";
  id.Freeze();
  const Clock::time_point wait_began = Clock::now();
  id.Settle();  // a whole model selection on 300 samples: far longer than a few periods
  const auto waited = Clock::now() - wait_began;
  ASSERT_EQ(id.refits(), 1);
  ASSERT_GE(waited, 3 * kPeriod) << "the closing refit ended too soon to test the wait";
  ASSERT_FALSE(calls.empty());
  EXPECT_GE(calls.size(), 2u) << "the hook was called once, then the wait went silent";
  // Every call came while the refit was still in flight, and never more often than the period.
  for (int64_t r : refits_at_call) EXPECT_EQ(r, 0);
  for (std::size_t i = 1; i < calls.size(); ++i) EXPECT_GE(calls[i] - calls[i - 1], kPeriod);
  const std::size_t calls_before = calls.size();
  id.Settle();  // nothing in flight: no wait, no call
  EXPECT_EQ(calls.size(), calls_before);
}

// Issue 61 finding 6: a landing whose wait hook gives up (a SIGTERM, an overrun) cancels the
// refit within a training pass, counts it as failed with the reason, and the model still predicts
// and keeps learning.
TEST(OnlineIdentifier, AWaitThatGivesUpCancelsTheRefitAndKeepsTheModel) {
  const Series train = testing::NarendraTrain(400);
  RefitSchedule refit;
  refit.first = 1000;  // only the freeze's closing refit
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  int calls = 0;
  id.SetRefitWaitHook([&] { return ++calls >= 2 ? RefitWait::kGiveUp : RefitWait::kKeepWaiting; },
                      std::chrono::milliseconds(1));
  for (Eigen::Index k = 0; k < 300; ++k) id.Push(Row(train, k));
  const std::string before = id.model().ToJson().dump();
  id.Freeze();
  id.Settle();  // a whole model selection: far longer than two 1 ms periods
  ASSERT_GE(calls, 2) << "the refit ended before the wait could give up";
  EXPECT_EQ(id.refits(), 0);
  EXPECT_EQ(id.failed_refits(), 1);
  EXPECT_NE(id.last_refit_failure().find("given up"), std::string::npos) << id.last_refit_failure();
  EXPECT_EQ(id.model().ToJson().dump(), before) << "the model changed though the refit was dropped";
  EXPECT_TRUE(id.model().Predict(Eigen::VectorXd::Zero(id.model().spec().size())).allFinite());
}

TEST(OnlineIdentifier, ARefitWithTooFewSamplesKeepsTheModel) {
  const Series train = testing::NarendraTrain(40);
  RefitSchedule refit;
  refit.first = 8;  // far too few rows for a hold-out and cross-validation folds
  refit.buffer = 8;
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) id.Push(Row(train, k));
  id.Freeze();
  id.Settle();
  EXPECT_EQ(id.refits(), 0);
  EXPECT_GE(id.failed_refits(), 1);
  // The reason is the refit's own (issue 61), not a guess.
  EXPECT_FALSE(id.last_refit_failure().empty());
  EXPECT_NE(id.last_refit_failure(), "cancelled");
  EXPECT_TRUE(id.model().Predict(Eigen::VectorXd::Zero(id.model().spec().size())).allFinite());
}

// Issue 61 finding 1: after a RESET (an empty model put in) with scheduled refits, the model
// learns again per sample at once, instead of predicting with no rule until a refit lands.
TEST(OnlineIdentifier, AResetModelLearnsPerSampleAgainThoughRefitsHadLanded) {
  const Series train = testing::NarendraTrain(700);
  RefitSchedule refit;
  refit.first = 200;
  refit.every = 0;
  refit.buffer = 5000;
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  Eigen::Index k = 0;
  for (; k < 450; ++k) id.Push(Row(train, k));
  id.Settle();
  ASSERT_GE(id.refits(), 1);
  id.ReplaceModel(Empty(fuzzy::ConsequentKind::kLinear, train));
  ASSERT_EQ(id.model().total_rules(), 0);
  for (const Eigen::Index end = k + 10; k < end; ++k) id.Push(Row(train, k));
  EXPECT_GT(id.model().total_rules(), 0) << "the reset model learns nothing per sample";
}

// Issue 61 finding 2: a model put back at sample N (a divergence restore) keeps learning, and
// its schedule counts from there: the next refit lands inside the run, not at the schedule's next
// point past N.
TEST(OnlineIdentifier, ARestoredModelKeepsLearningAndRefitsInsideTheRun) {
  const Series train = testing::NarendraTrain(1200);
  RefitSchedule refit;
  refit.first = 100;
  refit.every = 0;
  refit.buffer = 5000;
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  Eigen::Index k = 0;
  for (; k < 450; ++k) id.Push(Row(train, k));
  id.Settle();
  ASSERT_GE(id.refits(), 1);
  id.ReplaceModel(id.model(), id.samples_learned());
  const std::string restored = id.model().ToJson().dump();
  for (const Eigen::Index end = k + 10; k < end; ++k) id.Push(Row(train, k));
  EXPECT_NE(id.model().ToJson().dump(), restored) << "the restored model is frozen";
  const int64_t before = id.refits();
  for (const Eigen::Index end = k + 300; k < end; ++k) id.Push(Row(train, k));
  id.Settle();
  EXPECT_GT(id.refits(), before) << "no refit landed in the 310 samples after the restore";
}

TEST(RefitSchedule, SeriesFromSamplesBreaksWhereAnIndexIsSkipped) {
  std::deque<Sample> kept;
  for (int64_t k : {4, 5, 6, 9, 10})
    kept.push_back({k, Eigen::VectorXd::Constant(1, double(k)), Eigen::VectorXd::Zero(2)});
  const Series s = SeriesFromSamples(kept);
  EXPECT_EQ(s.samples(), 5);
  ASSERT_EQ(s.breaks.size(), 1u);
  EXPECT_EQ(s.breaks[0], 3);
  EXPECT_EQ(s.outputs(3, 0), 9.0);
}

// A long run's refit keeps the most recent samples and whole blocks spread evenly over all that
// came before them, at a fixed cost (docs/identifier.md §6.3).
TEST(RefitSchedule, TheBufferKeepsTheRecentSamplesAndBlocksSpreadOverTheWholeRun) {
  RefitSchedule schedule;
  schedule.first = 1;
  schedule.buffer = 1200;
  schedule.history = 0.5;
  ASSERT_EQ(schedule.HistoryBlock(), 100);
  ASSERT_EQ(schedule.RecentSamples(), 600);
  ScheduledRefitter refitter(schedule);
  const auto sample = [](int64_t k) {
    return Sample{k, Eigen::VectorXd::Constant(1, double(k)), Eigen::VectorXd::Zero(1)};
  };
  int64_t doublings = 0;
  for (int64_t n = 1; n <= 20000; ++n) {
    const int64_t stride = refitter.history_stride();
    const std::size_t before = refitter.kept();
    refitter.Keep(sample(n - 1));
    // Every sample until the buffer is full, then full, short of it only just after a doubling of
    // the stride dropped every other archived block (at most three of the six), until refilled.
    if (refitter.history_stride() != stride) {
      ++doublings;
      ASSERT_GE(refitter.kept(), 1200u - 300u) << n;
    } else {
      ASSERT_EQ(refitter.kept(), std::min<std::size_t>(before + 1, 1200)) << n;
    }
    ASSERT_LE(refitter.kept(), 1200u) << n;
    if (n % 997 != 0 && n != 20000) continue;
    const Series s = refitter.KeptSeries();
    const auto index = [&s](Eigen::Index r) { return static_cast<int64_t>(s.outputs(r, 0)); };
    ASSERT_EQ(index(0), 0) << "the run's first sample is kept";
    // From the back: at least the 600 most recent samples, in a run.
    Eigen::Index r = s.samples() - 1;
    while (r > 0 && index(r - 1) == index(r) - 1) --r;
    ASSERT_GE(s.samples() - r, 600) << n;
    ASSERT_EQ(index(s.samples() - 1), n - 1);
    // Before them (the block the run starts in may be archived too): whole blocks
    // b·100 … b·100 + 99 for b = 0, stride, 2·stride, … in order.
    const int64_t st = refitter.history_stride();
    const Eigen::Index archived = (index(r) / 100 % st == 0) ? r - index(r) % 100 : r;
    for (Eigen::Index q = 0; q < archived; ++q)
      ASSERT_EQ(index(q), (q / 100) * st * 100 + q % 100) << n << " row " << q;
    // Spread over the whole run: the gap before the recent run is under two strides of blocks.
    if (archived > 0) {
      ASSERT_LT(index(r) - index(archived - 1), 2 * st * 100 + 1) << n;
    }
  }
  EXPECT_GE(doublings, 4) << "20 000 samples over 600 archived: strides 2, 4, 8, 16";
  // Shorter blocks than kShortestHistoryBlock: the most recent samples only, as with history 0.
  schedule.buffer = 500;
  EXPECT_EQ(schedule.HistoryBlock(), 0);
  ScheduledRefitter recent_only(schedule);
  for (int64_t k = 0; k < 10000; ++k) recent_only.Keep(sample(k));
  const Series last = recent_only.KeptSeries();
  ASSERT_EQ(last.samples(), 500);
  EXPECT_TRUE(last.breaks.empty());
  EXPECT_EQ(last.outputs(0, 0), 9500.0);
}

// A selecting refit keeps the last refit's model when it predicts the refit's newest samples
// (its hold-out, which neither saw) better than the candidate the selection chose, by the margin
// a candidate needs over a simpler one, and passes the checks a refit's own model passes.
TEST(RefitSchedule, TheIncumbentStaysOnlyWhenItBeatsTheChoiceOnTheNewestSamples) {
  const Series series = testing::NarendraTrain(1500);
  NarxModel incumbent = Empty(fuzzy::ConsequentKind::kLinear, series);
  TrainOptions t;
  t.fit_scaling = false;
  Train(incumbent, SliceSeries(series, 0, 1000), t);
  SelectionResult selection;
  selection.fit_samples = 1200;
  selection.holdout_samples = 300;
  selection.free_run_criterion = true;
  selection.criterion_horizon = 0;
  Candidate linear;
  linear.linear = true;
  linear.rules = 1;
  linear.rest_deviation = 0.0;
  selection.candidates = {linear};
  selection.chosen = 0;
  const double held = incumbent.NdeiAhead(SliceSeries(series, 1200, 300), 0);
  ASSERT_TRUE(std::isfinite(held));
  const SelectionOptions options;  // 5 % or 0.005 NDEI
  selection.candidates[0].score = 2.0 * held + 0.01;
  EXPECT_TRUE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  // Within the margin the fresher choice lands.
  selection.candidates[0].score = std::max(1.04 * held, held + 0.004);
  EXPECT_FALSE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  selection.candidates[0].score = 0.5 * held;
  EXPECT_FALSE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  // A hold-out that is not the buffer's newest samples (a search on blocks) is no such test.
  selection.candidates[0].score = 2.0 * held + 0.01;
  selection.fit_samples = 1100;
  EXPECT_FALSE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  // A fuzzy incumbent must also beat the linear candidate there (issue 47): the chosen fuzzy
  // candidate faced the linear model in cross-validation, the incumbent never did.
  ASSERT_GT(incumbent.total_rules(), 1);
  selection.fit_samples = 1200;
  Candidate fuzzy;
  fuzzy.rules = 3;
  fuzzy.score = 2.0 * held + 0.01;  // the incumbent beats the choice by far
  fuzzy.rest_deviation = 0.0;
  selection.candidates = {linear, fuzzy};
  selection.chosen = 1;
  selection.candidates[0].score = 0.5 * held;  // but the linear model beats the incumbent
  EXPECT_FALSE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  selection.candidates[0].score = std::max(1.04 * held, held + 0.004);  // within the margin
  EXPECT_FALSE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
  selection.candidates[0].score = 2.0 * held + 0.01;  // beaten by the margin: it stays
  EXPECT_TRUE(IncumbentHoldsItsOwn(incumbent, selection, series, options));
}

// A steady-state refit trains with no hold-out; it lands only when its model passes the checks
// its selection held a model to: a finite score by the criterion (free run, or K steps ahead for
// a loop that integrates), and at rest where the linear model is.
TEST(RefitSchedule, ASteadyStateRefitLandsOnlyAModelThatPassesItsSelectionsChecks) {
  const Series series = testing::NarendraTrain(1500);
  // One rule whose consequent maps y(k) to 2 m − y(k), m the mean output: a free run from any
  // start swings about m for ever (a slope of −1), or away from it (a slope below −1).
  const auto swinging = [&](double slope) {
    fuzzy::FuzzyModelConfig cfg;
    cfg.entropy.threshold = 0.0;  // no rule beyond the first
    NarxModel m(testing::NarendraSpec(), cfg);
    m.SetScaling(ScalingFromRanges(m.spec(), RangesFromSeries(m.spec(), series)));
    TrainOptions t;
    t.fit_scaling = false;
    Train(m, SliceSeries(series, 0, 200), t);
    EXPECT_EQ(m.model(0).rules(), 1);
    const RegressionData d = BuildRegression(m.spec(), series);
    const double mean = series.outputs.col(0).mean();
    Eigen::MatrixXd x(d.x.rows(), d.x.cols());
    Eigen::VectorXd y(d.x.rows());
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
      x.row(k) = m.scaling().ScaleRegressor(d.x.row(k).transpose()).transpose();
      y(k) = m.scaling().ScaleOutput(0, mean + slope * (d.x(k, 0) - mean));
    }
    EXPECT_TRUE(m.mutable_model(0).RefineConsequents(x, y, 1e-12, 0.0));
    return m;
  };
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const NarxModel swings = swinging(-1.0);
  ASSERT_TRUE(std::isfinite(swings.NdeiAhead(series, 0)));
  const double rest = RestDeviation(swings, series);
  ASSERT_GT(rest, 0.05) << "the model does not swing at rest";
  // No rest check without the free-run criterion's linear candidate: a finite free run passes.
  EXPECT_TRUE(SteadyStateHolds(swings, series, 0, nan));
  // Where the linear model comes to rest, the swinging one is refused; where the linear model
  // swings nearly as much, it is not.
  EXPECT_FALSE(SteadyStateHolds(swings, series, 0, 0.0));
  EXPECT_TRUE(SteadyStateHolds(swings, series, 0, rest / 5.0));
  // A model that runs away in free run is refused in free run, and not 3 steps ahead, where a
  // loop that integrates is scored.
  const NarxModel runs_away = swinging(-1.5);
  EXPECT_FALSE(std::isfinite(runs_away.NdeiAhead(series, 0)));
  EXPECT_FALSE(SteadyStateHolds(runs_away, series, 0, nan));
  EXPECT_TRUE(SteadyStateHolds(runs_away, series, 3, nan));
  // A model trained on the plant passes both.
  NarxModel trained = Empty(fuzzy::ConsequentKind::kLinear, series);
  TrainOptions t;
  t.fit_scaling = false;
  Train(trained, series, t);
  EXPECT_TRUE(SteadyStateHolds(trained, series, 0, 0.0));
}

// At a landing, the linear model trained beside the refit lands instead of the fuzzy one only
// when, on the samples that came in meanwhile, it beats it by the candidates' margin and predicts
// them better than their own mean.
TEST(RefitSchedule, TheLinearModelLandsOnlyWhenItWinsTheNewSamples) {
  const Series series = testing::NarendraTrain(1500);
  const auto scaled = [&](NarxModel m) {
    m.SetScaling(ScalingFromRanges(m.spec(), RangesFromSeries(m.spec(), series)));
    return m;
  };
  fuzzy::FuzzyModelConfig one_rule;
  one_rule.entropy.threshold = 0.0;  // no rule beyond the first: ARX
  NarxModel linear = scaled(NarxModel(testing::NarendraSpec(), one_rule));
  TrainOptions t;
  t.fit_scaling = false;
  Train(linear, series, t);
  ASSERT_EQ(linear.total_rules(), 1);
  NarxModel fuzzy = Empty(fuzzy::ConsequentKind::kLinear, series);
  Train(fuzzy, series, t);
  ASSERT_GT(fuzzy.total_rules(), 1);
  const double l = linear.NdeiAhead(series, 0), f = fuzzy.NdeiAhead(series, 0);
  ASSERT_LT(l, 1.0);
  ASSERT_LT(f, l / 1.05 - 0.005) << "the fuzzy model must beat ARX on this plant";
  // The fuzzy model that predicts better stays; so does one no worse than the linear model.
  EXPECT_FALSE(LinearWinsTheNewSamples(fuzzy, linear, series, 0));
  EXPECT_FALSE(LinearWinsTheNewSamples(linear, linear, series, 0));
  // One that runs away in free run (to the output limits the model keeps) loses to it.
  NarxModel runs_away = linear;
  Eigen::VectorXd theta = runs_away.model(0).consequent().Parameters();
  theta *= 10.0;
  runs_away.mutable_model(0).mutable_consequent().SetParameters(theta);
  ASSERT_GT(runs_away.NdeiAhead(series, 0), 1.0);
  EXPECT_TRUE(LinearWinsTheNewSamples(runs_away, linear, series, 0));
  // A linear model no better than the samples' mean decides nothing, nor do a few samples.
  NarxModel mean_only = linear;
  mean_only.mutable_model(0).mutable_consequent().SetParameters(0.0 * theta);
  ASSERT_GE(mean_only.NdeiAhead(series, 0), 1.0);
  EXPECT_FALSE(LinearWinsTheNewSamples(runs_away, mean_only, series, 0));
  EXPECT_FALSE(LinearWinsTheNewSamples(runs_away, linear, SliceSeries(series, 0, 8), 0));
}

// The two refit tests' identifier: the default configuration at declared ranges, refits begun at
// 500 samples and landing at 1 000, then at every 1 000.
NarxModel EmptyOn(const SignalRanges& declared) {
  NarxModel empty(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{});
  empty.SetScaling(ScalingFromRanges(empty.spec(), declared));
  return empty;
}
RefitSchedule RefitsFrom500Every1000() {
  RefitSchedule refit;
  refit.first = 500;
  refit.every = 1000;
  return refit;
}

// A plant that drifts out of the range its first refit learned, into one where the fuzzy model's
// nearest rule has an unstable local model (the linear one's single slope stays stable): y(k+1) =
// (0.5 + 1.2 min(y(k)², 0.2)) y(k) + u(k), u in [−0.25, 0.25] for 1 000 samples, then in
// [0, 0.45]. Before the envelope (docs/identifier.md §7.3) the refit's fuzzy model ran away on the
// second range and the landing judgement put ARX in its place; now, outside the data it was
// trained on, its predictions are its global linear model's, so it no longer loses there and
// lands, and those samples are counted as outside.
TEST(OnlineIdentifier, OutsideItsDataARefitsFuzzyModelFallsBackToItsLinearModel) {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> first(-0.25, 0.25), second(0.0, 0.45);
  std::normal_distribution<double> noise(0.0, 0.002);
  const Eigen::Index n = 2010;
  Series s;
  s.inputs.resize(n, 1);
  s.outputs = Eigen::MatrixXd::Zero(n, 1);
  for (Eigen::Index k = 0; k < n; k += 5) {
    const double u = k < 1000 ? first(rng) : second(rng);
    for (Eigen::Index j = k; j < std::min(n, k + 5); ++j) s.inputs(j, 0) = u;
  }
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    const double y = s.outputs(k, 0);
    s.outputs(k + 1, 0) = (0.5 + 1.2 * std::min(y * y, 0.2)) * y + s.inputs(k, 0);
  }
  for (Eigen::Index k = 0; k < n; ++k) s.outputs(k, 0) += noise(rng);
  OnlineIdentifier id(EmptyOn({{"y", {-3.0, 3.0}}, {"u", {-1.0, 1.0}}}), RefitsFrom500Every1000());
  Eigen::Index k = 0;
  for (; k <= 1000; ++k) id.Push(Row(s, k));
  // The refit begun at 500 landed at 1 000: its fuzzy model won the samples of the first range.
  ASSERT_EQ(id.refits(), 1);
  EXPECT_EQ(id.linear_landed(), 0);
  EXPECT_GT(id.model().total_rules(), 1);
  const int64_t outside_before = id.samples_outside();
  for (; k < n; ++k) id.Push(Row(s, k));
  ASSERT_EQ(id.refits(), 2);
  EXPECT_EQ(id.linear_landed(), 0) << "the fuzzy model no longer loses the new samples";
  EXPECT_GT(id.model().total_rules(), 1);
  ASSERT_TRUE(id.model().envelope().any());
  // The fuzzy model, tracked since it landed, predicts the second range in free run.
  EXPECT_LT(id.model().NdeiAhead(SliceSeries(s, 1000, n - 1000), 0), 0.5);
  // The second range lies outside what the first refit's model was trained on.
  EXPECT_GT(id.samples_outside() - outside_before, 100);
  EXPECT_LE(id.samples_outside(), id.samples_predicted());
}

// A plant whose curvature goes away inside the range it was learned in: y(k+1) = 0.5 y(k) + u(k)
// + 0.8 u(k)² for 1 000 samples, then y(k+1) = 0.5 y(k) + u(k), u uniform in [−1, 1] throughout.
// The refit begun at 1 000 fits the curvature (a fuzzy model) and ARX beside it; on the samples
// that come in while it runs, the fuzzy model predicts a curvature that is gone and ARX (a
// constant offset) predicts them better, by more than the margin: ARX lands at 2 000, then
// learns those samples (CatchUp) and tracks, so it is ARX on every sample.
TEST(OnlineIdentifier, ARefitWhoseFuzzyModelLosesTheNewSamplesLandsTheLinearOneAndCatchesUp) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> input(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 0.002);
  const Eigen::Index n = 2010;
  Series s;
  s.inputs.resize(n, 1);
  s.outputs = Eigen::MatrixXd::Zero(n, 1);
  for (Eigen::Index k = 0; k < n; ++k) s.inputs(k, 0) = input(rng);
  for (Eigen::Index k = 0; k + 1 < n; ++k) {
    const double u = s.inputs(k, 0);
    s.outputs(k + 1, 0) = 0.5 * s.outputs(k, 0) + u + (k < 1000 ? 0.8 * u * u : 0.0);
  }
  for (Eigen::Index k = 0; k < n; ++k) s.outputs(k, 0) += noise(rng);
  OnlineIdentifier id(EmptyOn({{"y", {-4.0, 4.0}}, {"u", {-1.0, 1.0}}}), RefitsFrom500Every1000());
  Eigen::Index k = 0;
  for (; k <= 1000; ++k) id.Push(Row(s, k));
  ASSERT_EQ(id.refits(), 1);
  EXPECT_GT(id.model().total_rules(), 1) << "the curvature makes the first refit's model fuzzy";
  for (; k < n; ++k) id.Push(Row(s, k));
  ASSERT_EQ(id.refits(), 2);
  EXPECT_EQ(id.linear_landed(), 1);
  EXPECT_EQ(id.model().total_rules(), 1);
  // It learned the samples that came in while its refit ran, and tracked since: it is ARX on
  // every sample, not on the 1 001 its refit had.
  const ArxModel everything = ArxModel::Fit(id.model().spec(), s);
  const Series refit_samples = SliceSeries(s, 0, 1001);  // samples 0 … 1 000
  const ArxModel refit_only = ArxModel::Fit(id.model().spec(), refit_samples);
  const RegressionData rows = BuildRegression(id.model().spec(), s);
  double to_everything = 0, to_refit_only = 0;
  for (Eigen::Index r = 0; r < rows.x.rows(); ++r) {
    const Eigen::VectorXd x = rows.x.row(r).transpose();
    const double live = id.model().Predict(x)(0);
    to_everything = std::max(to_everything, std::abs(live - everything.Predict(x)(0)));
    to_refit_only = std::max(to_refit_only, std::abs(live - refit_only.Predict(x)(0)));
  }
  EXPECT_LT(to_everything, 1e-5);  // the tracker's prior has a relative ridge of 1e-6
  EXPECT_GT(to_refit_only, 1e-3);
  // Exactly once each: the ARX's tracker learned every row after the refit's, the catch-up's and
  // the tracked ones since, none twice.
  EXPECT_EQ(id.tracked(),
            rows.x.rows() - BuildRegression(id.model().spec(), refit_samples).x.rows());
}

// An expert's rules (issue 47 point 4): an identifier started from a model someone gave keeps
// its rules through the refits, their consequents refined on the vehicle's samples, unless a
// refit's own choice beats them on its hold-out by the margin; then they are replaced, once.
TEST(OnlineIdentifier, AnExpertsRulesSurviveTheRefitsUnlessBeaten) {
  const Series expert_data = testing::NarendraTrain(1500, 3);
  const Series flight = testing::NarendraTrain(1600, 4);
  RefitSchedule refit;
  refit.first = 500;
  refit.every = 1000;
  refit.buffer = 5000;
  OfflineFitOptions fo;
  fo.selection.simulation = DefaultSimulationStages();
  fo.selection.consequents = {fuzzy::ConsequentKind::kLinear};
  const NarxModel empty = Empty(fuzzy::ConsequentKind::kLinear, expert_data);
  // A good expert: odonata-fit's model of the same plant.
  // The expert named its rules' terms (as a .fis's membership functions): the names stay with
  // the rules through the refits that refine them (issue 47 point 4).
  NarxModelState named =
      FitOffline(empty.spec(), empty.model(0).config(), TrainOptions{}, expert_data, fo)
          .model.State();
  for (std::size_t j = 0; j < named.models[0].rules.size(); ++j) {
    auto& n = named.models[0].rules[j].names;
    n.terms.assign(static_cast<std::size_t>(empty.spec().size()), "");
    n.terms[0] = "term" + std::to_string(j);
    n.output = "regime" + std::to_string(j);
  }
  const NarxModel good = NarxModel::FromState(named);
  ASSERT_GT(good.total_rules(), 1);
  ASSERT_TRUE(good.model(0).named());
  OnlineIdentifier kept(good, refit);
  kept.KeepExpertRules();
  ASSERT_TRUE(kept.has_expert());
  for (Eigen::Index k = 0; k < flight.samples(); ++k) kept.Push(Row(flight, k));
  kept.Freeze();
  kept.Settle();
  EXPECT_GE(kept.experts_kept(), 1);
  EXPECT_FALSE(kept.expert_replaced());
  ASSERT_EQ(kept.model().total_rules(), good.total_rules()) << "the expert's rules stay";
  for (int j = 0; j < good.total_rules(); ++j)
    for (int i = 0; i < good.spec().size(); ++i)
      EXPECT_EQ(kept.model().model(0).rule_base().centre(j, i),
                good.model(0).rule_base().centre(j, i));
  for (int j = 0; j < good.total_rules(); ++j)
    EXPECT_EQ(kept.model().model(0).names(j), good.model(0).names(j)) << "rule " << j;
  // And in the model file, read back.
  const NarxModel reread = NarxModel::FromJson(kept.model().ToJson());
  EXPECT_EQ(reread.model(0).names(1).output, "regime1");
  EXPECT_EQ(reread.model(0).names(1).terms[0], "term1");
  // A linear "expert" on this strongly nonlinear plant: the first refit's choice beats it.
  fuzzy::FuzzyModelConfig one = empty.model(0).config();
  one.entropy.threshold = 0.0;  // no rule beyond the first (the refits search H̄ themselves)
  NarxModel linear(empty.spec(), one);
  linear.SetScaling(empty.scaling());
  TrainOptions t;
  t.fit_scaling = false;
  Train(linear, expert_data, t);
  ASSERT_EQ(linear.total_rules(), 1);
  OnlineIdentifier replaced(linear, refit);
  replaced.KeepExpertRules();
  for (Eigen::Index k = 0; k < flight.samples(); ++k) replaced.Push(Row(flight, k));
  replaced.Freeze();
  replaced.Settle();
  EXPECT_TRUE(replaced.expert_replaced());
  EXPECT_FALSE(replaced.has_expert()) << "once replaced, later refits are free";
  EXPECT_GT(replaced.model().total_rules(), 1);
}

TEST(OnlineIdentifier, ReportsAPrioriPredictionsAndAFreeRun) {
  const Series train = testing::NarendraTrain(800);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train));
  PushResult r;
  EXPECT_FALSE(id.Push(Row(train, 0), &r).has_value());  // filling the regressor
  EXPECT_EQ(r, PushResult::kAccepted);
  double last_err = 0;
  for (Eigen::Index k = 1; k < train.samples(); ++k) {
    const auto rep = id.Push(Row(train, k));
    ASSERT_TRUE(rep.has_value());
    EXPECT_EQ(rep->index, k);
    EXPECT_EQ(rep->measured(0), train.outputs(k, 0));
    EXPECT_TRUE(rep->free_run.allFinite());
    EXPECT_TRUE(rep->next.allFinite());
    last_err = std::abs(rep->predicted(0) - rep->measured(0));
  }
  EXPECT_LT(last_err, 2.0);
  EXPECT_GT(id.model().total_rules(), 1);
}

// Issue 47 point 5: with a horizon the identifier reports ŷ(k | k−K) for the model and the live
// ARX, exactly as odonata-fit's PredictAhead computes them on the same series with the same
// model — so the monitor's K-step score is odonata-fit's, not a look-alike.
TEST(OnlineIdentifier, KStepPredictionsAreOdonataFitsPredictAheadBitForBit) {
  const Series train = testing::NarendraTrain(1200);
  const Series check = testing::NarendraTrain(700, /*seed=*/9);
  constexpr int kHorizon = 12;
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train));
  EXPECT_THROW(id.set_ahead_horizon(1), std::invalid_argument);
  id.set_ahead_horizon(kHorizon);
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    const auto rep = id.Push(Row(train, k));
    if (rep) {
      EXPECT_EQ(rep->ahead.size(), 1);
    }
  }
  id.Freeze();
  // A new run: the history restarts at the gap, as a segment starts offline.
  std::vector<double> ahead, arx_ahead;
  for (Eigen::Index k = 0; k < check.samples(); ++k) {
    Sample s = Row(check, k);
    s.index += train.samples() + 10;
    if (const auto rep = id.Push(s)) {
      ahead.push_back(rep->ahead(0));
      arx_ahead.push_back(rep->arx_ahead(0));
    }
  }
  const NarxModel& model = id.model();
  const RecursiveArx& arx = id.arx();
  const Eigen::MatrixXd want = PredictAhead(
      model.spec(), check, [&](const Eigen::VectorXd& x) { return model.Predict(x); }, kHorizon);
  const Eigen::MatrixXd want_arx = PredictAhead(
      model.spec(), check, [&](const Eigen::VectorXd& x) { return arx.Predict(x); }, kHorizon);
  ASSERT_EQ(static_cast<Eigen::Index>(ahead.size()), want.rows());
  for (Eigen::Index r = 0; r < want.rows(); ++r) {
    ASSERT_EQ(ahead[static_cast<std::size_t>(r)], want(r, 0)) << "row " << r;
    ASSERT_EQ(arx_ahead[static_cast<std::size_t>(r)], want_arx(r, 0)) << "row " << r;
  }
  // And K steps ahead is not one step ahead: the comparison above is not of copies.
  EXPECT_GT((want - PredictOneStep(model.spec(), check,
                                   [&](const Eigen::VectorXd& x) { return model.Predict(x); }))
                .cwiseAbs()
                .maxCoeff(),
            1e-3);
}

TEST(OnlineIdentifier, GapsRestartTheHistoryAndAreCounted) {
  const Series train = testing::NarendraTrain(50);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kSingleton, train));
  for (Eigen::Index k = 0; k < 10; ++k) id.Push(Row(train, k));
  PushResult r;
  EXPECT_FALSE(id.Push(Row(train, 13), &r).has_value());  // no regressor across the gap
  EXPECT_EQ(r, PushResult::kGap);
  EXPECT_EQ(id.gaps(), 3);
  EXPECT_TRUE(id.Push(Row(train, 14)).has_value());
}

// Issue 24 point 7: in real time each lost sample restarted the history (ny samples of warm-up
// more per gap: 617 of 1027 samples learned at 5 % loss). Gaps up to max_gap are bridged by the
// straight line between their neighbours, which is what odonata-fit --max-gap learns from the
// exported log: the model equals the one learned from the series with the rows so filled.
TEST(OnlineIdentifier, ShortGapsAreBridgedAsOdonataFitBridgesMissingRows) {
  const Series train = testing::NarendraTrain(400);
  const std::vector<Eigen::Index> lost = {50, 51, 120, 200, 201, 202};  // gaps of 2, 1 and 3
  auto is_lost = [&](Eigen::Index k) { return std::count(lost.begin(), lost.end(), k) > 0; };
  Series filled = train;
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    if (!is_lost(k)) continue;
    Eigen::Index a = k, b = k;
    while (is_lost(a)) --a;
    while (is_lost(b)) ++b;
    const double w = double(k - a) / double(b - a);  // series_from_table.cpp's arithmetic
    for (Eigen::Index c = 0; c < train.outputs.cols(); ++c)
      filled.outputs(k, c) = train.outputs(a, c) + w * (train.outputs(b, c) - train.outputs(a, c));
    for (Eigen::Index c = 0; c < train.inputs.cols(); ++c)
      filled.inputs(k, c) = train.inputs(a, c) + w * (train.inputs(b, c) - train.inputs(a, c));
  }
  OnlineIdentifier bridging(Empty(fuzzy::ConsequentKind::kLinear, train));
  bridging.set_max_gap(3);
  OnlineIdentifier reference(Empty(fuzzy::ConsequentKind::kLinear, train));
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    reference.Push(Row(filled, k));
    if (is_lost(k)) continue;
    PushResult r;
    const auto rep = bridging.Push(Row(train, k), &r);
    if (k == 52 || k == 121 || k == 203) {
      EXPECT_EQ(r, PushResult::kBridged) << k;
      ASSERT_TRUE(rep.has_value()) << "no warm-up after a bridged gap";
      EXPECT_EQ(rep->index, k);
    }
  }
  EXPECT_EQ(bridging.model().ToJson().dump(), reference.model().ToJson().dump());
  EXPECT_EQ(bridging.samples_learned(), reference.samples_learned());
  EXPECT_EQ(bridging.gaps(), 6);
  EXPECT_EQ(bridging.bridged(), 6);
  // Longer than max_gap: the history restarts, as before.
  Sample far = Row(train, train.samples() - 1);
  far.index = train.samples() + 4;  // 4 missing after the last sample, 399
  PushResult r;
  EXPECT_FALSE(bridging.Push(far, &r).has_value());
  EXPECT_EQ(r, PushResult::kGap);
  EXPECT_EQ(bridging.gaps(), 10);
  EXPECT_EQ(bridging.bridged(), 6);
}

TEST(OnlineIdentifier, RejectsDuplicatesAndNonFiniteSamplesWithoutTouchingTheModel) {
  const Series train = testing::NarendraTrain(50);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kSingleton, train));
  for (Eigen::Index k = 0; k < 20; ++k) id.Push(Row(train, k));
  const std::string before = id.model().ToJson().dump();
  PushResult r;
  EXPECT_FALSE(id.Push(Row(train, 5), &r).has_value());
  EXPECT_EQ(r, PushResult::kDuplicate);
  Sample bad = Row(train, 20);
  bad.outputs(0) = NAN;
  EXPECT_FALSE(id.Push(bad, &r).has_value());
  EXPECT_EQ(r, PushResult::kRejected);
  bad = Row(train, 20);
  bad.inputs(0) = INFINITY;
  EXPECT_FALSE(id.Push(bad, &r).has_value());
  EXPECT_EQ(id.model().ToJson().dump(), before);
  EXPECT_TRUE(id.Push(Row(train, 20)).has_value());
}

TEST(OnlineIdentifier, FrozenModelDoesNotLearn) {
  const Series train = testing::NarendraTrain(200);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kSingleton, train));
  for (Eigen::Index k = 0; k < 100; ++k) id.Push(Row(train, k));
  id.Freeze();
  const std::string before = id.model().ToJson().dump();
  for (Eigen::Index k = 100; k < 200; ++k) EXPECT_FALSE(id.Push(Row(train, k))->learned);
  EXPECT_EQ(id.model().ToJson().dump(), before);
}

TEST(SignalRanges, ScalingAndJsonRoundTrip) {
  RegressorSpec spec{2, 1, 1, {"y"}, {"u"}};
  const SignalRanges r{{"y", {-2.0, 4.0}}, {"u", {0.0, 1.0}}};
  const Scaling s = ScalingFromRanges(spec, r);
  EXPECT_EQ(s.regressor_mid(0), 1.0);
  EXPECT_EQ(s.regressor_half(1), 3.0);
  EXPECT_EQ(s.regressor_mid(2), 0.5);
  EXPECT_EQ(s.output_std(0), 3.0);
  EXPECT_EQ(RangesFromJson(RangesToJson(r)), r);
  EXPECT_THROW(ScalingFromRanges(spec, {{"y", {0, 1}}}), std::runtime_error);
  EXPECT_THROW(ScalingFromRanges(spec, {{"y", {1, 1}}, {"u", {0, 1}}}), std::runtime_error);
}

}  // namespace
}  // namespace odonata::sysid

namespace odonata::sysid {
namespace {

// One meaning per number (issue 57): the free run a frozen identifier publishes over a new run is
// odonata-fit's free run (SimulateFreeRun) of the same model on the same samples, sample by sample,
// with lags of 2 and a K-step horizon as the Flapper's pitch loop has them.
TEST(OnlineIdentifier, AFrozenModelsFreeRunIsOdonataFitsFreeRun) {
  const Series train = testing::NarendraTrain(1500);
  RegressorSpec spec = testing::NarendraSpec();
  spec.output_lags = 2;
  spec.input_lags = 2;
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  NarxModel model(spec, cfg);
  model.SetScaling(ScalingFromRanges(spec, RangesFromSeries(spec, train)));
  TrainOptions o;
  o.epochs = 2;
  Train(model, train, o);
  const Series run = testing::NarendraTrain(600);
  const Predictor predict = [&model](const Eigen::VectorXd& x) { return model.Predict(x); };
  const Eigen::MatrixXd offline = SimulateFreeRun(spec, run, predict);
  for (const int horizon : {0, 20}) {
    SCOPED_TRACE(horizon);
    OnlineIdentifier online(model);
    online.set_ahead_horizon(horizon);
    online.Freeze();
    Eigen::Index r = 0;
    for (Eigen::Index k = 0; k < run.samples(); ++k) {
      const auto rep = online.Push(Row(run, k));
      if (!rep) continue;
      ASSERT_LT(r, offline.rows());
      EXPECT_EQ(rep->free_run(0), offline(r, 0)) << "sample " << k;
      ++r;
    }
    EXPECT_EQ(r, offline.rows());
  }
}

}  // namespace
}  // namespace odonata::sysid

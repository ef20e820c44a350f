#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "narendra_series.hpp"
#include "sysid/online_identifier.hpp"
#include "sysid/signal_ranges.hpp"

namespace odonata::sysid {
namespace {

Sample Row(const Series& s, Eigen::Index k) {
  return {k, s.outputs.row(k).transpose(), s.inputs.row(k).transpose()};
}

NarxModel Empty(fuzzy::ConsequentKind kind, const Series& train) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  NarxModel m(testing::NarendraSpec(), cfg);
  m.SetScaling(ScalingFromRanges(m.spec(), RangesFromSeries(m.spec(), train)));
  return m;
}

TEST(OnlineIdentifier, ReproducesTheOfflineTrainerBitForBit) {
  const Series train = testing::NarendraTrain(1500);
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    NarxModel offline = Empty(kind, train);
    TrainOptions o;
    o.refine_least_squares = false;
    o.fit_scaling = false;
    offline.Train(train, o);
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
  for (int64_t n : {100, 200, 400, 1000, 1500}) EXPECT_TRUE(paced.Due(n)) << n;
  for (int64_t n : {500, 800, 1200, 1600}) EXPECT_FALSE(paced.Due(n)) << n;
  EXPECT_FALSE(RefitSchedule{}.Due(100)) << "off by default";
}

// One learner, two schedules: with refits at fixed counts the online identifier still equals
// odonata-fit's online pass bit for bit; with linear consequents it also predicts better.
TEST(OnlineIdentifier, ScheduledRefitsReproduceTheOfflinePassAndLearnBetter) {
  const Series train = testing::NarendraTrain(1500);
  const Series validate = testing::NarendraValidate(500);
  RefitSchedule refit;
  refit.first = 100;
  refit.every = 400;
  refit.buffer = 600;
  refit.epochs = 0;  // least squares only: premise epochs between growth steps can stall it (§6.3)
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    NarxModel offline = Empty(kind, train), plain = Empty(kind, train);
    TrainOptions o;
    o.refine_least_squares = false;
    o.fit_scaling = false;
    plain.Train(train, o);
    o.refit = refit;
    offline.Train(train, o);
    OnlineIdentifier online(Empty(kind, train), refit);
    for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(train, k));
    EXPECT_EQ(online.model().ToJson().dump(), offline.ToJson().dump()) << ToString(kind);
    // 100, 200, 400, 800, 1200 of the 1499 samples learned.
    EXPECT_EQ(online.refits(), 5) << ToString(kind);
    std::printf("%s: validation one-step NDEI %.4f with refits, %.4f without\n", ToString(kind),
                offline.Ndei(validate, false), plain.Ndei(validate, false));
    // Linear consequents: the global least squares over the kept rows beats the per-rule RLS.
    if (kind == fuzzy::ConsequentKind::kLinear)
      EXPECT_LT(offline.Ndei(validate, false), plain.Ndei(validate, false));
  }
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

#include <cmath>
#include <cstdio>
#include <fstream>

#include <limits>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "metrics/accuracy.hpp"
#include "narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {
namespace {

using testing::NarendraSpec;
using testing::NarendraTrain;
using testing::NarendraValidate;

NarxModel TrainedModel(fuzzy::ConsequentKind kind) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  NarxModel m(NarendraSpec(), cfg);
  TrainOptions o;
  o.epochs = 2;
  Train(m, NarendraTrain(1500), o);
  return m;
}

std::string TempPath(const std::string& name) { return ::testing::TempDir() + "/" + name; }

TEST(NarxModel, SameDataSameModelBitForBit) {
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    EXPECT_EQ(TrainedModel(kind).ToJson().dump(), TrainedModel(kind).ToJson().dump());
  }
}

TEST(NarxModel, OnlyTheFirstEpochGrowsRulesLaterOnesTune) {
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    fuzzy::FuzzyModelConfig cfg;
    cfg.consequent = kind;
    TrainOptions o;
    o.epochs = 1;
    NarxModel one(NarendraSpec(), cfg), five(NarendraSpec(), cfg);
    Train(one, NarendraTrain(1500), o);
    o.epochs = 5;
    Train(five, NarendraTrain(1500), o);
    ASSERT_GT(one.total_rules(), 1);
    EXPECT_EQ(five.total_rules(), one.total_rules());
    // …but they did tune: the parameters moved.
    EXPECT_NE(five.ToJson().dump(), one.ToJson().dump());
  }
}

// After the pass that grows rules, a rule the training rows cannot support is removed before the
// least-squares solve; the online learner (no least squares) never prunes this way.
TEST(NarxModel, TrainingRemovesRulesTheDataCannotSupport) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.threshold = ThresholdForRadius(0.6);
  TrainOptions keep_all;
  keep_all.min_rule_support = 0.0;
  TrainOptions demanding;
  demanding.min_rule_support = 1e6;  // no rule is supported: only the best-supported one stays
  NarxModel all(NarendraSpec(), cfg), pruned(NarendraSpec(), cfg), online(NarendraSpec(), cfg);
  Train(all, NarendraTrain(600), keep_all);
  Train(pruned, NarendraTrain(600), demanding);
  demanding.refine_least_squares = false;
  Train(online, NarendraTrain(600), demanding);
  ASSERT_GT(all.total_rules(), 2);
  EXPECT_EQ(pruned.total_rules(), 1);
  EXPECT_EQ(online.total_rules(), all.total_rules());
}

TEST(NarxModel, SaveThenLoadGivesIdenticalPredictions) {
  for (auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    const NarxModel a = TrainedModel(kind);
    const std::string path = TempPath("model.json");
    a.Save(path);
    const NarxModel b = NarxModel::Load(path);
    const Series v = NarendraValidate();
    const auto pa =
        PredictOneStep(a.spec(), v, [&](const Eigen::VectorXd& x) { return a.Predict(x); });
    const auto pb =
        PredictOneStep(b.spec(), v, [&](const Eigen::VectorXd& x) { return b.Predict(x); });
    EXPECT_EQ(pa, pb);  // exact equality
    EXPECT_EQ(a.ToJson().dump(), b.ToJson().dump());
  }
}

TEST(NarxModel, LoadNamesTheFileAndTheProblem) {
  auto expect_error = [](const std::string& path, const std::string& fragment) {
    try {
      NarxModel::Load(path);
      ADD_FAILURE() << "no error for " << path;
    } catch (const std::runtime_error& e) {
      const std::string msg = e.what();
      EXPECT_NE(msg.find(path), std::string::npos) << msg;
      EXPECT_NE(msg.find(fragment), std::string::npos) << msg;
    }
  };
  expect_error(TempPath("does-not-exist.json"), "cannot open");
  const std::string garbage = TempPath("garbage.json");
  std::ofstream(garbage) << "{ not json";
  expect_error(garbage, "not valid JSON");
  const std::string foreign = TempPath("foreign.json");
  std::ofstream(foreign) << R"({"hello": 1})";
  expect_error(foreign, "not an odonata model");
  nlohmann::json j = TrainedModel(fuzzy::ConsequentKind::kSingleton).ToJson();
  j["models"][0]["inputs"] = 5;
  const std::string wrong = TempPath("wrong.json");
  std::ofstream(wrong) << j.dump();
  expect_error(wrong, "");
}

TEST(NarxModel, SeveralOutputsShareOneRegressor) {
  // Two outputs of one plant: y1 follows Narendra, y2 = 0.5 y1(k) + u(k).
  Series s = NarendraTrain(2000);
  s.outputs.conservativeResize(Eigen::NoChange, 2);
  s.outputs(0, 1) = 0;
  for (Eigen::Index t = 1; t < s.samples(); ++t)
    s.outputs(t, 1) = 0.5 * s.outputs(t - 1, 0) + s.inputs(t - 1, 0);
  RegressorSpec spec{1, 1, 1, {"y1", "y2"}, {"u"}};
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  NarxModel m(spec, cfg);
  Train(m, s, TrainOptions{});
  EXPECT_EQ(m.outputs(), 2);
  EXPECT_EQ(m.spec().size(), 3);  // y1(k), y2(k), u(k)
  Eigen::VectorXd x(3);
  x << 0.4, 0.1, 0.3;
  const Eigen::VectorXd y = m.Predict(x);
  EXPECT_NEAR(y(1), 0.5 * 0.4 + 0.3, 0.05);  // a linear map the linear consequents learn
}

TEST(FreeRun, UsesOwnPredictionsAndMeasuredInitialConditions) {
  Series s;
  s.inputs = Eigen::MatrixXd::Ones(6, 1);
  s.outputs = Eigen::MatrixXd::Constant(6, 1, 50.0);  // measured values the free run must ignore
  s.outputs(0, 0) = 1.0;
  RegressorSpec spec{1, 1, 1, {"y"}, {"u"}};
  const Predictor twice = [](const Eigen::VectorXd& x) {
    return Eigen::VectorXd::Constant(1, 2 * x(0) + x(1));
  };
  const Eigen::MatrixXd sim = SimulateFreeRun(spec, s, twice);
  ASSERT_EQ(sim.rows(), 5);
  EXPECT_EQ(sim(0, 0), 3.0);
  EXPECT_EQ(sim(1, 0), 7.0);
  EXPECT_EQ(sim(4, 0), 63.0);
  const Predictor nan = [](const Eigen::VectorXd&) { return Eigen::VectorXd::Constant(1, NAN); };
  bool diverged = false;
  const Eigen::MatrixXd held = SimulateFreeRun(spec, s, nan, &diverged);
  EXPECT_TRUE(diverged);
  EXPECT_TRUE(held.allFinite());
}

TEST(NarxModel, TrainingFitNeverFallsFromOneEpochToTheNext) {
  for (auto kind : {fuzzy::ConsequentKind::kLinear, fuzzy::ConsequentKind::kSingleton}) {
    fuzzy::FuzzyModelConfig cfg;
    cfg.consequent = kind;
    cfg.entropy.threshold = 0.5;
    cfg.entropy.kappa = 0.5;
    NarxModel m(testing::NarendraSpec(), cfg);
    TrainOptions o;
    o.epochs = 25;
    o.ridge = 0.0;
    const TrainReport r = Train(m, testing::NarendraTrain(1500), o);
    ASSERT_EQ(r.epochs.size(), 25u);
    for (std::size_t k = 1; k < r.epochs.size(); ++k)
      EXPECT_GE(r.epochs[k].train_fit, r.epochs[k - 1].train_fit) << ToString(kind) << " " << k;
    EXPECT_GT(r.epochs.back().train_fit, r.epochs.front().train_fit);
  }
}

TEST(NarxModel, HoldoutKeepsTheBestEpoch) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.threshold = 0.5;
  cfg.entropy.kappa = 0.5;
  NarxModel m(testing::NarendraSpec(), cfg);
  const Series all = testing::NarendraTrain(2000);
  Series fit, hold;
  fit.outputs = all.outputs.topRows(1600);
  fit.inputs = all.inputs.topRows(1600);
  hold.outputs = all.outputs.bottomRows(400);
  hold.inputs = all.inputs.bottomRows(400);
  TrainOptions o;
  o.epochs = 15;
  o.holdout = &hold;
  const TrainReport r = Train(m, fit, o);
  double best = std::numeric_limits<double>::infinity();
  int best_epoch = 0;
  for (const auto& e : r.epochs)
    if (e.accepted && e.holdout_ndei < best) {
      best = e.holdout_ndei;
      best_epoch = e.epoch;
    }
  EXPECT_EQ(r.kept_epoch, best_epoch);
  EXPECT_NEAR(m.Ndei(hold, true), best, 1e-12);
}

// What the K-step tests predict with: a model of Narendra's plant, two epochs on 1 000 samples.
NarxModel NarendraModel() {
  NarxModel m(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{});
  TrainOptions t;
  t.epochs = 2;
  Train(m, testing::NarendraTrain(1000), t);
  return m;
}

// K steps ahead sits between one step (K = 1) and the free run (K beyond the record).
TEST(NarxModel, PredictAheadSpansOneStepToFreeRun) {
  const NarxModel m = NarendraModel();
  const Series v = testing::NarendraValidate(300);
  const Predictor p = [&m](const Eigen::VectorXd& x) { return m.Predict(x); };
  const RegressorSpec& spec = m.spec();
  EXPECT_EQ(PredictAhead(spec, v, p, 1), PredictOneStep(spec, v, p));
  EXPECT_EQ(PredictAhead(spec, v, p, 1000), SimulateFreeRun(spec, v, p));
  const double one = m.NdeiAhead(v, 1), five = m.NdeiAhead(v, 5), free = m.NdeiAhead(v, 0);
  EXPECT_EQ(one, m.Ndei(v, false));
  EXPECT_EQ(free, m.Ndei(v, true));
  EXPECT_LE(one, five);
  EXPECT_LE(five, free * 1.05);
  // Row r of a 3-step prediction is a free run of 3 steps from the measured outputs before it.
  const Eigen::MatrixXd three = PredictAhead(spec, v, p, 3);
  const auto targets = TargetRows(spec, v);
  const Series window =
      SliceSeries(v, targets[10] - 2 - spec.first_target(), spec.first_target() + 3);
  EXPECT_DOUBLE_EQ(three(10, 0), SimulateFreeRun(spec, window, p)(2, 0));
}

// A stride predicts every m-th target, counted back from the last, exactly as without it, and
// leaves the rest unpredicted; the sampled score is the score of those rows.
TEST(NarxModel, PredictAheadWithAStrideSamplesTheTargets) {
  const NarxModel m = NarendraModel();
  const Series v = testing::NarendraValidate(300);
  const Predictor p = [&m](const Eigen::VectorXd& x) { return m.Predict(x); };
  const Eigen::MatrixXd all = PredictAhead(m.spec(), v, p, 5);
  const Eigen::MatrixXd sampled = PredictAhead(m.spec(), v, p, 5, nullptr, 4);
  ASSERT_EQ(sampled.rows(), all.rows());
  const Eigen::Index n = all.rows();
  Eigen::Index predicted = 0;
  for (Eigen::Index r = 0; r < n; ++r) {
    if ((n - 1 - r) % 4 == 0) {
      EXPECT_EQ(sampled(r, 0), all(r, 0)) << "row " << r;
      ++predicted;
    } else {
      EXPECT_TRUE(std::isnan(sampled(r, 0))) << "row " << r;
    }
  }
  EXPECT_EQ(predicted, (n + 3) / 4);
  const Eigen::MatrixXd y = Targets(m.spec(), v);
  Eigen::VectorXd yk(predicted), yhk(predicted);
  for (Eigen::Index i = 0, r = (n - 1) % 4; r < n; ++i, r += 4) {
    yk(i) = y(r, 0);
    yhk(i) = all(r, 0);
  }
  EXPECT_DOUBLE_EQ(m.NdeiAhead(v, 5, 4), metrics::Score(yk, yhk).ndei);
  EXPECT_EQ(m.NdeiAhead(v, 5, 1), m.NdeiAhead(v, 5));
}

}  // namespace
}  // namespace odonata::sysid

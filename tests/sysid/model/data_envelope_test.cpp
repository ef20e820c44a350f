// Outside the data, the global linear model (docs/identifier.md §7.3).

#include <cmath>
#include <random>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "metrics/accuracy.hpp"
#include "narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {
namespace {

// The Narendra plant driven by u uniform in [lo, hi], seeded.
Series NarendraBetween(double lo, double hi, int samples, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(lo, hi);
  Eigen::VectorXd u(samples);
  for (int k = 0; k < samples; ++k) u(k) = dist(rng);
  return testing::NarendraSeries(u);
}

fuzzy::FuzzyModelConfig LinearConfig() {
  fuzzy::FuzzyModelConfig c;
  c.consequent = fuzzy::ConsequentKind::kLinear;
  return c;
}

// A fuzzy model trained on `train` with the envelope (three epochs of least squares, a rule base
// grown at the default H̄), and the same model without it.
NarxModel Trained(const Series& train, bool envelope) {
  fuzzy::FuzzyModelConfig c = LinearConfig();
  c.entropy.threshold = DefaultThresholds()[4];  // several rules on this record
  NarxModel m(testing::NarendraSpec(), c);
  TrainOptions t;
  t.epochs = 3;
  t.fit_envelope = envelope;
  Train(m, train, t);
  return m;
}

double FreeRunFit(const RegressorSpec& spec, const Series& s, const Predictor& predict) {
  const Eigen::MatrixXd yhat = SimulateFreeRun(spec, s, predict, nullptr);
  return metrics::Score(Targets(spec, s).col(0), yhat.col(0)).fit_percent;
}

TEST(DataEnvelope, InsideTheTrainingRowsThePredictionIsTheRulesOwn) {
  const Series train = NarendraBetween(-2.0, 2.0, 800, 3);
  const NarxModel with = Trained(train, true);
  NarxModel without = with;
  without.SetEnvelope(DataEnvelope{});
  ASSERT_TRUE(with.envelope().any());
  ASSERT_GT(with.total_rules(), 1);
  const RegressionData d = BuildRegression(with.spec(), train);
  for (Eigen::Index r = 0; r < d.x.rows(); ++r) {
    Eigen::VectorXd share;
    const Eigen::VectorXd y = with.Predict(d.x.row(r).transpose(), &share);
    ASSERT_EQ(y(0), without.Predict(d.x.row(r).transpose())(0)) << "row " << r;
    ASSERT_EQ(share(0), 0.0) << "row " << r;
  }
}

TEST(DataEnvelope, FarOutsideThePredictionIsTheGlobalLinearModel) {
  const Series train = NarendraBetween(-2.0, 2.0, 800, 3);
  const NarxModel m = Trained(train, true);
  // Least squares on the same rows in raw units: the envelope's linear model, unscaled.
  const ArxModel arx = ArxModel::Fit(m.spec(), train);
  for (const double scale : {10.0, -25.0, 100.0}) {
    const Eigen::Vector2d x(scale, -scale);  // y(k-1), u(k-1) far beyond anything trained on
    Eigen::VectorXd share;
    const double y = m.Predict(x, &share)(0);
    EXPECT_EQ(share(0), 1.0) << scale;
    EXPECT_NEAR(y, arx.Predict(x)(0), 1e-6 * std::abs(arx.Predict(x)(0))) << scale;
  }
}

TEST(DataEnvelope, TheBlendIsSmoothAndMonotoneInTheDistance) {
  DataEnvelope e;
  e.outputs.push_back(OutputEnvelope{Eigen::Vector2d(1.0, 0.0), 2.0});
  e.lower = Eigen::VectorXd::Constant(1, -1.0);
  e.upper = Eigen::VectorXd::Constant(1, 1.0);
  const Eigen::VectorXd x = Eigen::VectorXd::Zero(1);
  EXPECT_EQ(e.LinearShare(0, x, 0.0), 0.0);
  EXPECT_EQ(e.LinearShare(0, x, 2.0), 0.0);
  EXPECT_EQ(e.LinearShare(0, x, 2.0 + DataEnvelope::kBlendWidths), 1.0);
  EXPECT_EQ(e.LinearShare(0, x, 1e9), 1.0);
  EXPECT_EQ(e.LinearShare(0, x, std::nan("")), 0.0) << "NaN stays the fuzzy NaN";
  double last = 0.0;
  for (double d = 2.0; d <= 3.0; d += 0.01) {
    const double s = e.LinearShare(0, x, d);
    EXPECT_GE(s, last);
    last = s;
  }
  EXPECT_NEAR(e.LinearShare(0, x, 2.5), 0.5, 1e-12);
  // Outside the box [-1, 1] (span 2): the linear model from kBoxBlendSpan · 2 beyond it.
  const Eigen::VectorXd edge = Eigen::VectorXd::Constant(1, 1.0);
  const Eigen::VectorXd out = Eigen::VectorXd::Constant(1, 1.0 + 2.0 * DataEnvelope::kBoxBlendSpan);
  const Eigen::VectorXd mid = Eigen::VectorXd::Constant(1, 1.0 + DataEnvelope::kBoxBlendSpan);
  EXPECT_EQ(e.LinearShare(0, edge, 0.0), 0.0);
  EXPECT_EQ(e.LinearShare(0, out, 0.0), 1.0);
  EXPECT_NEAR(e.LinearShare(0, mid, 0.0), 0.5, 1e-12);
  EXPECT_NEAR(e.LinearShare(0, -mid, 0.0), 0.5, 1e-12);
  EXPECT_EQ(e.Blend(0, x, 3.0, e.LinearShare(0, x, 1.0)), 3.0);
  EXPECT_EQ(e.Blend(0, x, 3.0, e.LinearShare(0, x, 4.0)), 1.0);
  EXPECT_NEAR(e.Blend(0, x, 3.0, e.LinearShare(0, x, 2.5)), 2.0, 1e-12);
}

TEST(DataEnvelope, ARoundTripThroughAModelFileKeepsEveryPrediction) {
  const Series train = NarendraBetween(-2.0, 2.0, 600, 5);
  const NarxModel m = Trained(train, true);
  const NarxModel back = NarxModel::FromJson(nlohmann::json::parse(m.ToJson().dump()));
  EXPECT_EQ(back.ToJson().dump(), m.ToJson().dump());
  const Eigen::Vector2d far(50.0, 3.0);
  EXPECT_EQ(back.Predict(far)(0), m.Predict(far)(0));
}

TEST(DataEnvelope, AMalformedEnvelopeIsRefusedWithItsField) {
  const Series train = NarendraBetween(-2.0, 2.0, 600, 5);
  nlohmann::json j = Trained(train, true).ToJson();
  j["data_envelope"]["outputs"][0]["radius_widths"] = -1.0;
  try {
    NarxModel::FromJson(j);
    FAIL() << "a negative radius was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("radius_widths"), std::string::npos) << e.what();
  }
  j = Trained(train, true).ToJson();
  j["data_envelope"]["outputs"][0]["linear"] = {1.0, 2.0};  // one short
  EXPECT_THROW(NarxModel::FromJson(j), std::runtime_error);
}

TEST(DataEnvelope, AOneRuleModelHasNone) {
  const Series train = NarendraBetween(-2.0, 2.0, 400, 5);
  fuzzy::FuzzyModelConfig one = LinearConfig();
  one.entropy.max_rules = 1;
  NarxModel linear(testing::NarendraSpec(), one);
  TrainOptions t;
  t.fit_envelope = true;
  Train(linear, train, t);
  ASSERT_EQ(linear.total_rules(), 1);
  EXPECT_FALSE(linear.envelope().any()) << "a one-rule model is linear already";
}

// The test: trained on half of the plant's range, scored on all of it. Outside the half
// it trained on, the model must not follow its nearest rule out of range: odonata-fit's defaults
// are never below ARX by more than half a FIT point there.
TEST(DataEnvelope, TrainedOnHalfTheRangeAModelIsNeverBelowArxOnAllOfIt) {
  const Series half = NarendraBetween(0.0, 2.0, 1000, 11);
  const Series all = NarendraBetween(-2.0, 2.0, 1000, 12);
  OfflineFitOptions fo;
  fo.selection.simulation = DefaultSimulationStages();
  fo.selection.consequents = {fuzzy::ConsequentKind::kLinear};
  const OfflineFit fit =
      FitOffline(testing::NarendraSpec(), LinearConfig(), TrainOptions{}, half, fo);
  const ArxModel arx = ArxModel::Fit(testing::NarendraSpec(), half);
  const RegressorSpec spec = testing::NarendraSpec();
  const double fuzzy_one =
      metrics::Score(
          Targets(spec, all).col(0),
          PredictOneStep(spec, all, [&](const Eigen::VectorXd& x) { return fit.model.Predict(x); })
              .col(0))
          .fit_percent;
  const double arx_one =
      metrics::Score(
          Targets(spec, all).col(0),
          PredictOneStep(spec, all, [&](const Eigen::VectorXd& x) { return arx.Predict(x); })
              .col(0))
          .fit_percent;
  const double fuzzy_free =
      FreeRunFit(spec, all, [&](const Eigen::VectorXd& x) { return fit.model.Predict(x); });
  const double arx_free =
      FreeRunFit(spec, all, [&](const Eigen::VectorXd& x) { return arx.Predict(x); });
  std::printf(
      "half range -> all of it: fuzzy (%d rules) %.2f %% one step, %.2f %% free run; "
      "ARX %.2f %%, %.2f %%\n",
      fit.model.total_rules(), fuzzy_one, fuzzy_free, arx_one, arx_free);
  EXPECT_GE(fuzzy_one, arx_one - 0.5);
  EXPECT_GE(fuzzy_free, arx_free - 0.5);
}

}  // namespace
}  // namespace odonata::sysid

// Local interval widths (fit/local_spread.hpp; issue 60 point 1): on a plant whose noise is ten
// times larger for positive inputs than for negative ones, a fuzzy model's σ̂ is wider where the
// noise is, the normalised conformal interval keeps its level over the whole and is narrower on
// the whole than one width for all; outside the data, σ̂ grows with the distance.
#include "fit/local_spread.hpp"

#include <gtest/gtest.h>

#include "fit/prediction_intervals.hpp"
#include "linear_plant.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::fit {
namespace {

sysid::RegressorSpec LocalSpec() { return testing::LinearPlantSpec(); }

// The noise ten times larger for positive inputs: σ 0.02 below 0, 0.2 above.
sysid::Series NoisyPlant(unsigned seed, int samples) {
  return testing::LinearPlant(seed, samples, 0.02, 0.2);
}

// A fuzzy model with linear consequents whose rules can tell the input's regimes apart.
sysid::NarxModel FuzzyModelOf(const sysid::Series& train) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = sysid::ThresholdForRadius(1.0);
  sysid::NarxModel model(LocalSpec(), cfg);
  sysid::TrainOptions t;
  t.epochs = 5;
  sysid::Train(model, train, t);
  return model;
}

struct RegimeTally {
  double covered[2] = {0, 0}, width[2] = {0, 0}, n[2] = {0, 0};
};

// One-step coverage and mean width by regime (u(t−1) below or above 0) on `s`.
RegimeTally ByRegime(const sysid::NarxModel& m, const sysid::Series& s, const IntervalWidths& w) {
  const Eigen::MatrixXd y = sysid::Targets(LocalSpec(), s);
  const Eigen::MatrixXd yhat =
      sysid::PredictOneStep(LocalSpec(), s, [&](const Eigen::VectorXd& x) { return m.Predict(x); });
  const Eigen::MatrixXd half = w.HalfWidths("one_step", w.spread.At(LocalSpec(), s));
  RegimeTally t;
  for (Eigen::Index r = 0; r < y.rows(); ++r) {
    const int k = s.inputs(r, 0) < 0 ? 0 : 1;  // target r is sample r + 1
    t.n[k] += 1;
    t.covered[k] += std::abs(y(r, 0) - yhat(r, 0)) <= half(r, 0) ? 1 : 0;
    t.width[k] += 2 * half(r, 0);
  }
  for (int k = 0; k < 2; ++k) {
    t.covered[k] /= t.n[k];
    t.width[k] /= t.n[k];
  }
  return t;
}

TEST(LocalSpread, WidensWhereTheNoiseIsAndKeepsItsLevelOverall) {
  const sysid::Series train = NoisyPlant(1, 4000), calibration = NoisyPlant(2, 2000),
                      test = NoisyPlant(3, 4000);
  const sysid::NarxModel model = FuzzyModelOf(train);
  ASSERT_GE(model.total_rules(), 2) << "rules to tell the regimes apart";
  const sysid::Predictor predict = [&](const Eigen::VectorXd& x) { return model.Predict(x); };
  const IntervalWidths uniform = CalibrateIntervals(LocalSpec(), calibration, predict, 0, 0.9);
  const IntervalWidths local =
      CalibrateIntervals(LocalSpec(), calibration, predict, 0, 0.9, LocalSpread::Fit(model, train));
  ASSERT_TRUE(local.spread.fitted());
  const RegimeTally u = ByRegime(model, test, uniform), l = ByRegime(model, test, local);
  EXPECT_GT(l.width[1], 2.0 * l.width[0]) << "wider where the noise is";
  EXPECT_DOUBLE_EQ(u.width[1], u.width[0]) << "one width for all";
  // The guarantee is marginal either way: about 90 % over both regimes together, and narrower on
  // the whole. (Per regime, the coverage follows how sharply the rules part the regimes: four
  // soft rules here, and the noisy one stays near 78 % either way.)
  const auto both = [](const RegimeTally& t, const double* v) {
    return (v[0] * t.n[0] + v[1] * t.n[1]) / (t.n[0] + t.n[1]);
  };
  EXPECT_NEAR(both(l, l.covered), 0.9, 0.03);
  EXPECT_NEAR(both(u, u.covered), 0.9, 0.03);
  EXPECT_LT(both(l, l.width), 0.85 * both(u, u.width));
}

// A sample outside the data the rules were fitted on: the farther, the wider.
TEST(LocalSpread, WidensOutsideTheData) {
  const sysid::Series train = NoisyPlant(1, 4000);
  const sysid::NarxModel model = FuzzyModelOf(train);
  const LocalSpread spread = LocalSpread::Fit(model, train);
  sysid::Series inside = NoisyPlant(5, 400), far = inside, farther = inside;
  far.inputs *= 3.0;
  farther.inputs *= 6.0;
  const double in = spread.At(LocalSpec(), inside).mean();
  const double out = spread.At(LocalSpec(), far).mean();
  EXPECT_GT(out, 1.2 * in) << "a third of the inputs inside, the rest out to 3 times the range";
  EXPECT_GT(spread.At(LocalSpec(), farther).mean(), 1.5 * out);
  EXPECT_TRUE(spread.At(LocalSpec(), farther).allFinite());
}

TEST(LocalSpread, NotFittedItIsOneEverywhere) {
  const LocalSpread none;
  EXPECT_FALSE(none.fitted());
  const Eigen::MatrixXd s = none.At(LocalSpec(), NoisyPlant(1, 50));
  EXPECT_EQ(s.rows(), 49);
  EXPECT_TRUE((s.array() == 1.0).all());
}

}  // namespace
}  // namespace odonata::fit

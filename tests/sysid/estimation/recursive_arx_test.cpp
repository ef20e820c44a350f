// The live ARX baseline (docs/identifier.md §6.4): recursive least squares that ends where the
// batch ArxModel does on the same samples, and the identifier reports it beside the fuzzy model.
#include <gtest/gtest.h>

#include "narendra_series.hpp"
#include "sysid/estimation/consequent_tracker.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/estimation/recursive_arx.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::sysid {
namespace {

TEST(RecursiveArx, EndsWhereBatchLeastSquaresDoesOnTheSameSamples) {
  const Series train = testing::NarendraTrain(1500);
  const RegressorSpec spec = testing::NarendraSpec();
  const RegressionData d = BuildRegression(spec, train);
  const Scaling scaling = Scaling::FromData(d.x, d.y);
  RecursiveArx live(scaling);
  for (Eigen::Index r = 0; r < d.x.rows(); ++r)
    live.Update(d.x.row(r).transpose(), d.y.row(r).transpose());
  EXPECT_EQ(live.samples(), d.x.rows());
  const ArxModel batch = ArxModel::Fit(spec, train);
  const Series validate = testing::NarendraValidate(500);
  const RegressionData v = BuildRegression(spec, validate);
  double worst = 0, range = v.y.maxCoeff() - v.y.minCoeff();
  for (Eigen::Index r = 0; r < v.x.rows(); ++r) {
    const Eigen::VectorXd x = v.x.row(r).transpose();
    worst = std::max(worst, (live.Predict(x) - batch.Predict(x)).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst, 1e-6 * range) << "the prior P0 = 1e6 I is a ridge of 1e-6 in scaled units";
  // Non-finite samples are not learned.
  Eigen::VectorXd bad = d.x.row(0).transpose();
  bad(0) = std::nan("");
  live.Update(bad, d.y.row(0).transpose());
  EXPECT_EQ(live.samples(), d.x.rows());
  live.Reset();
  EXPECT_EQ(live.samples(), 0);
  EXPECT_TRUE(live.coefficients().isZero());
}

TEST(OnlineIdentifier, ReportsTheLiveArxBesideTheFuzzyModelAndFreezesItWithTheModel) {
  const Series train = testing::NarendraTrain(1000);
  NarxModel empty(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{});
  empty.SetScaling(ScalingFromRanges(empty.spec(), RangesFromSeries(empty.spec(), train)));
  OnlineIdentifier id(empty);
  RecursiveArx mirror(empty.scaling());
  const RegressionData d = BuildRegression(empty.spec(), train);
  Eigen::Index row = 0;
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    const auto rep =
        id.Push({k, train.outputs.row(k).transpose(), train.inputs.row(k).transpose()});
    if (!rep) continue;
    // ŷ(k | k−1) comes before the sample is learned, as the fuzzy model's does.
    const Eigen::VectorXd x = d.x.row(row).transpose();
    EXPECT_EQ(rep->arx_predicted, mirror.Predict(x)) << k;
    mirror.Update(x, d.y.row(row).transpose());
    ASSERT_EQ(rep->arx_free_run.size(), 1);
    EXPECT_TRUE(rep->arx_free_run.allFinite());
    ++row;
  }
  EXPECT_EQ(id.arx().samples(), row);
  EXPECT_EQ(id.arx().coefficients(), mirror.coefficients());
  id.Freeze();
  id.Push({train.samples(), train.outputs.row(0).transpose(), train.inputs.row(0).transpose()});
  EXPECT_EQ(id.arx().samples(), row) << "a frozen identifier's baseline does not learn";
  // A replaced model (a resume) starts its baseline afresh.
  id.ReplaceModel(empty);
  EXPECT_EQ(id.arx().samples(), 0);
}

}  // namespace
}  // namespace odonata::sysid

namespace odonata::sysid {
namespace {

// Continued from the refit's factorisation (docs/identifier.md §6.3): from the least-squares
// consequents of the samples A and their covariance, recursive global least squares over the
// samples B ends at the least-squares consequents of A and B together, premises unchanged.
TEST(ConsequentTracker, ContinuesTheLeastSquaresProblemOfTheRefit) {
  const Series all = testing::NarendraTrain(1200);
  fuzzy::FuzzyModelConfig cfg;
  cfg.entropy.threshold = 0.5;  // a few rules, so the problem couples them
  NarxModel model(testing::NarendraSpec(), cfg);
  TrainOptions o;
  o.epochs = 3;
  Train(model, all, o);
  ASSERT_GE(model.model(0).rules(), 3);
  const auto part = [&](Eigen::Index from, Eigen::Index rows) {
    Series s;
    s.inputs = all.inputs.middleRows(from, rows);
    s.outputs = all.outputs.middleRows(from, rows);
    return s;
  };
  const Series a = part(0, 800), b = part(800, 400);
  const auto scaled = [&](const Series& s, Eigen::MatrixXd* x, Eigen::VectorXd* y) {
    const RegressionData d = BuildRegression(model.spec(), s);
    x->resize(d.x.rows(), d.x.cols());
    y->resize(d.x.rows());
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
      x->row(k) = model.scaling().ScaleRegressor(d.x.row(k).transpose()).transpose();
      (*y)(k) = model.scaling().ScaleOutput(0, d.y(k, 0));
    }
    return d;
  };
  Eigen::MatrixXd xa, xab;
  Eigen::VectorXd ya, yab;
  scaled(a, &xa, &ya);
  ASSERT_TRUE(model.mutable_model(0).RefineConsequents(xa, ya, 1e-10, 0.0));
  ConsequentTracker tracker = ConsequentTracker::Build(model, a, 1e-10);
  ASSERT_FALSE(tracker.empty());
  // The reference: least squares on A and B, the rows B contributes as the tracker sees them
  // (B's regressors start after its own lags, as a history restarted there would).
  NarxModel reference = model;
  const RegressionData db = BuildRegression(model.spec(), b);
  Eigen::MatrixXd xb;
  Eigen::VectorXd yb;
  scaled(b, &xb, &yb);
  xab.resize(xa.rows() + xb.rows(), xa.cols());
  xab << xa, xb;
  yab.resize(ya.size() + yb.size());
  yab << ya, yb;
  ASSERT_TRUE(reference.mutable_model(0).RefineConsequents(xab, yab, 1e-10, 0.0));
  const Eigen::VectorXd before = model.model(0).consequent().Parameters();
  for (Eigen::Index k = 0; k < db.x.rows(); ++k)
    tracker.Step(model, db.x.row(k).transpose(), db.y.row(k).transpose());
  EXPECT_EQ(tracker.steps(), db.x.rows());
  const Eigen::VectorXd tracked = model.model(0).consequent().Parameters();
  const Eigen::VectorXd expected = reference.model(0).consequent().Parameters();
  EXPECT_GT((tracked - before).norm(), 1e-6) << "the tracker did not move the consequents";
  EXPECT_LT((tracked - expected).norm(), 1e-5 * expected.norm())
      << "tracked " << tracked.transpose() << "\nbatch " << expected.transpose();
  // A model with another rule count is not the one it was built for: left alone.
  NarxModel other(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{});
  tracker.Step(other, db.x.row(0).transpose(), db.y.row(0).transpose());
  EXPECT_EQ(tracker.steps(), db.x.rows());
}

}  // namespace
}  // namespace odonata::sysid

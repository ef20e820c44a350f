// The live ARX baseline (docs/identifier.md §6.4): recursive least squares that ends where the
// batch ArxModel does on the same samples, and the identifier reports it beside the fuzzy model.
#include <gtest/gtest.h>

#include "narendra_series.hpp"
#include "sysid/arx_model.hpp"
#include "sysid/online_identifier.hpp"
#include "sysid/recursive_arx.hpp"
#include "sysid/signal_ranges.hpp"

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

// The consequents' least squares against an SVD reference (docs/identifier.md §6.1).

#include <random>

#include <gtest/gtest.h>
#include <Eigen/SVD>

#include "fuzzy/blockwise_least_squares.hpp"
#include "fuzzy/fuzzy_model.hpp"

namespace odonata::fuzzy {
namespace {

// Columns that are nearly collinear (condition number ≈ 1e9): the normal equations square it.
Eigen::MatrixXd IllConditioned(int rows, int cols, Eigen::VectorXd* b) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::MatrixXd a(rows, cols);
  for (int r = 0; r < rows; ++r) {
    const double base = n(rng);
    for (int c = 0; c < cols; ++c)
      a(r, c) = base + 1e-9 * c * n(rng) + (c == 0 ? 0.1 * n(rng) : 0.0);
  }
  b->resize(rows);
  for (int r = 0; r < rows; ++r) (*b)(r) = a.row(r).sum() + 0.01 * n(rng);
  return a;
}

Eigen::VectorXd Feed(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, int block, double ridge) {
  BlockwiseLeastSquares ls(a.cols());
  for (Eigen::Index start = 0; start < a.rows(); start += block) {
    const Eigen::Index rows = std::min<Eigen::Index>(block, a.rows() - start);
    ls.AddRows(a.middleRows(start, rows), b.segment(start, rows));
  }
  return ls.Solve(ridge);
}

TEST(BlockwiseLeastSquares, MatchesAnSvdReferenceOnAnIllConditionedDesign) {
  Eigen::VectorXd b;
  const Eigen::MatrixXd a = IllConditioned(3000, 6, &b);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  ASSERT_GT(svd.singularValues()(0) / svd.singularValues()(5), 1e7);
  const Eigen::VectorXd reference = svd.solve(b);
  for (int block : {1, 7, 500, 5000}) {
    const Eigen::VectorXd theta = Feed(a, b, block, 0.0);
    // Compare residuals (the minimiser is ill-determined along the near-null direction).
    EXPECT_NEAR((a * theta - b).norm(), (a * reference - b).norm(), 1e-9 * b.norm()) << block;
  }
}

TEST(BlockwiseLeastSquares, ASmallerRidgeNeverRaisesTheTrainingResidual) {
  Eigen::VectorXd b;
  const Eigen::MatrixXd a = IllConditioned(2000, 8, &b);
  double previous = std::numeric_limits<double>::infinity();
  for (double ridge : {1e-2, 1e-4, 1e-6, 1e-8, 1e-10, 1e-12, 0.0}) {
    const double residual = (a * Feed(a, b, 256, ridge) - b).norm();
    EXPECT_LE(residual, previous * (1 + 1e-12)) << "ridge " << ridge;
    previous = residual;
  }
}

TEST(BlockwiseLeastSquares, RankDeficientDesignGetsTheMinimumNormSolution) {
  Eigen::MatrixXd a(4, 3);
  a << 1, 1, 0, 2, 2, 1, 3, 3, 0, 4, 4, 1;  // columns 0 and 1 identical
  const Eigen::Vector4d b(1, 2, 3, 4);
  const Eigen::VectorXd theta = Feed(a, b, 2, 0.0);
  const Eigen::VectorXd reference =
      Eigen::JacobiSVD<Eigen::MatrixXd>(a, Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b);
  EXPECT_LT((theta - reference).norm(), 1e-10);
  EXPECT_NEAR(theta(0), theta(1), 1e-10) << "minimum norm splits the weight evenly";
}

TEST(BlockwiseLeastSquares, RefineConsequentsTrainingFitNeverFallsAsTheRidgeShrinks) {
  // The whole model: many overlapping rules make Φ nearly rank-deficient.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::MatrixXd x(1500, 2);
  Eigen::VectorXd y(1500);
  for (int k = 0; k < 1500; ++k) {
    x(k, 0) = u(rng);
    x(k, 1) = u(rng);
    y(k) = std::sin(3 * x(k, 0)) * x(k, 1);
  }
  FuzzyModelConfig cfg;
  cfg.inputs = 2;
  cfg.entropy.threshold = 0.52;
  cfg.entropy.kappa = 0.5;
  cfg.entropy.sigma_min = 0.05;
  FuzzyModel grown(cfg);
  for (int k = 0; k < 1500; ++k) grown.Learn(x.row(k).transpose(), y(k));
  ASSERT_GT(grown.rules(), 20);
  double previous = std::numeric_limits<double>::infinity();
  for (double ridge : {1e-3, 1e-6, 1e-9, 1e-12, 0.0}) {
    FuzzyModel m = grown;
    ASSERT_TRUE(m.RefineConsequents(x, y, ridge));
    double se = 0;
    for (int k = 0; k < 1500; ++k) se += std::pow(m.Predict(x.row(k).transpose()) - y(k), 2);
    EXPECT_LE(se, previous * (1 + 1e-9)) << "ridge " << ridge;
    previous = se;
  }
}

}  // namespace
}  // namespace odonata::fuzzy

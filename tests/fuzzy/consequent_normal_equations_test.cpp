// The consequents' normal equations against the dense problem they stand for, solved by a
// complete orthogonal decomposition of the whole weighted design (docs/identifier.md §6.1).

#include <random>

#include <gtest/gtest.h>
#include <Eigen/QR>
#include <Eigen/SVD>

#include "fuzzy/consequent_normal_equations.hpp"
#include "fuzzy/fuzzy_model.hpp"

namespace odonata::fuzzy {
namespace {

struct Rows {
  Eigen::ArrayXXd phi;  // rows × rules, each row summing to 1
  Eigen::MatrixXd z;    // rows × width
  Eigen::VectorXd y;
};

// Rules along a line, firing as Gaussians of a slowly moving scheduling variable: neighbouring
// rows fire the same few rules, far rules not at all (below the negligible firing), as on a flight.
Rows MakeRows(int rows, int rules, int width, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n(0.0, 1.0);
  Rows r{Eigen::ArrayXXd(rows, rules), Eigen::MatrixXd(rows, width), Eigen::VectorXd(rows)};
  for (int k = 0; k < rows; ++k) {
    const double s = double(rules) * (0.5 + 0.5 * std::sin(0.002 * k));
    for (int j = 0; j < rules; ++j) r.phi(k, j) = std::exp(-0.5 * (s - j) * (s - j) / 0.25);
    r.phi.row(k) /= r.phi.row(k).sum();
    r.z(k, width - 1) = 1.0;
    for (int c = 0; c + 1 < width; ++c) r.z(k, c) = n(rng);
    r.y(k) = std::sin(s) * r.z.row(k).sum() + 0.01 * n(rng);
  }
  return r;
}

// The dense reference: [Φ; √(λ s) I; √(μ s_δ) I_δ] θ = [y; 0; 0] by COD, s over Φ's columns.
Eigen::VectorXd Reference(const Rows& r, SharedPart shared, double ridge, double deviation) {
  const Eigen::Index rules = r.phi.cols(), w = r.z.cols(), n = r.y.size();
  const Eigen::Index off = shared == SharedPart::kGlobal ? w : 0, m = off + rules * w;
  Eigen::MatrixXd design(n, m);
  if (off > 0) design.leftCols(w) = r.z;
  for (Eigen::Index j = 0; j < rules; ++j)
    design.middleCols(off + j * w, w) = r.z.array().colwise() * r.phi.col(j);
  const double s = design.colwise().squaredNorm().mean();
  const double sd = design.rightCols(m - off).colwise().squaredNorm().mean();
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + 2 * m, m);
  a.topRows(n) = design;
  a.middleRows(n, m).diagonal().setConstant(std::sqrt(ridge * s));
  if (off > 0) a.bottomRows(m).diagonal().tail(m - off).setConstant(std::sqrt(deviation * sd));
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 2 * m);
  b.head(n) = r.y;
  const Eigen::VectorXd theta = Eigen::CompleteOrthogonalDecomposition<Eigen::MatrixXd>(a).solve(b);
  if (off == 0) return theta;
  Eigen::VectorXd own(rules * w);
  for (Eigen::Index j = 0; j < rules; ++j)
    own.segment(j * w, w) = theta.head(w) + theta.segment(off + j * w, w);
  return own;
}

Eigen::VectorXd Solve(const Rows& r, SharedPart shared, double ridge, double deviation,
                      Eigen::Index block) {
  ConsequentNormalEquations ne(int(r.phi.cols()), int(r.z.cols()), shared);
  for (Eigen::Index start = 0; start < r.y.size(); start += block) {
    const Eigen::Index rows = std::min(block, r.y.size() - start);
    ne.AddRows(r.phi.middleRows(start, rows), r.z.middleRows(start, rows),
               r.y.segment(start, rows));
  }
  EXPECT_EQ(ne.rows_added(), r.y.size());
  return ne.Solve(ridge, deviation);
}

TEST(ConsequentNormalEquations, EqualsTheDenseRidgeProblem) {
  const Rows r = MakeRows(3000, 12, 3, 1);
  const Eigen::VectorXd reference = Reference(r, SharedPart::kNone, 1e-10, 0.0);
  for (Eigen::Index block : {1, 50, 64, 2048, 5000}) {
    const Eigen::VectorXd theta = Solve(r, SharedPart::kNone, 1e-10, 0.0, block);
    EXPECT_LT((theta - reference).norm(), 1e-6 * reference.norm()) << "block " << block;
  }
}

TEST(ConsequentNormalEquations, EqualsTheDenseProblemWithASharedPartAndItsRidge) {
  const Rows r = MakeRows(2500, 8, 4, 2);
  for (double deviation : {0.01, 1.0, 100.0}) {
    const Eigen::VectorXd reference = Reference(r, SharedPart::kGlobal, 1e-10, deviation);
    const Eigen::VectorXd theta = Solve(r, SharedPart::kGlobal, 1e-10, deviation, 700);
    EXPECT_LT((theta - reference).norm(), 1e-6 * reference.norm()) << "ridge " << deviation;
  }
  // A very large deviation ridge leaves one global model: every rule's parameters alike.
  const Eigen::VectorXd global = Solve(r, SharedPart::kGlobal, 1e-10, 1e9, 700);
  for (int j = 1; j < 8; ++j)
    EXPECT_LT((global.segment(4 * j, 4) - global.head(4)).norm(), 1e-4 * global.head(4).norm());
}

TEST(ConsequentNormalEquations, RulesThatNeverFireGetZeroRatherThanNoise) {
  Rows r = MakeRows(1000, 6, 2, 3);
  r.phi.col(5).setZero();  // a rule far from every row
  r.phi.col(4) *= 1e-14;
  const Eigen::VectorXd theta = Solve(r, SharedPart::kNone, 1e-10, 0.0, 256);
  EXPECT_TRUE(theta.allFinite());
  EXPECT_EQ(theta.tail(4).norm(), 0.0);
}

TEST(ConsequentNormalEquations, WithoutARidgeARankDeficientDesignGetsTheMinimumNormSolution) {
  // Two rules that fire alike everywhere: only their sum is determined; minimum norm splits it.
  Rows r = MakeRows(400, 2, 2, 4);
  r.phi.col(0).setConstant(0.5);
  r.phi.col(1).setConstant(0.5);
  const Eigen::VectorXd theta = Solve(r, SharedPart::kNone, 0.0, 0.0, 64);
  Eigen::MatrixXd design(r.y.size(), 4);
  design << 0.5 * r.z, 0.5 * r.z;
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(design, Eigen::ComputeThinU | Eigen::ComputeThinV);
  svd.setThreshold(1e-10);
  const Eigen::VectorXd reference = svd.solve(r.y);
  EXPECT_LT((theta - reference).norm(), 1e-8 * reference.norm());
  EXPECT_NEAR(theta(0), theta(2), 1e-8);
}

TEST(ConsequentNormalEquations, NoRowsGiveZerosAndWrongShapesAreRefused) {
  ConsequentNormalEquations ne(3, 2, SharedPart::kNone);
  EXPECT_EQ(ne.Solve(1e-10), Eigen::VectorXd::Zero(6));
  EXPECT_THROW(ne.AddRows(Eigen::ArrayXXd::Zero(4, 2), Eigen::MatrixXd::Zero(4, 2),
                          Eigen::VectorXd::Zero(4)),
               std::invalid_argument);
  EXPECT_THROW(ConsequentNormalEquations(0, 2, SharedPart::kNone), std::invalid_argument);
}

// Lagged samples of a smooth signal are nearly collinear (here 1e-5 apart, a condition number of
// Φ near 1e6): the Gram matrix squares it, and the default ridge keeps the fit the dense one.
TEST(ConsequentNormalEquations, NearlyCollinearRegressorsFitAsTheDenseSolveDoes) {
  Rows r = MakeRows(4000, 5, 3, 6);
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  for (Eigen::Index k = 0; k < r.y.size(); ++k) r.z(k, 1) = r.z(k, 0) + 1e-5 * n(rng);
  const Eigen::VectorXd theta = Solve(r, SharedPart::kNone, 1e-10, 0.0, 2048);
  const Eigen::VectorXd reference = Reference(r, SharedPart::kNone, 1e-10, 0.0);
  Eigen::MatrixXd design(r.y.size(), 15);
  for (Eigen::Index j = 0; j < 5; ++j)
    design.middleCols(3 * j, 3) = r.z.array().colwise() * r.phi.col(j);
  const double dense = (design * reference - r.y).norm();
  EXPECT_NEAR((design * theta - r.y).norm(), dense, 1e-9 * dense);
}

TEST(ConsequentNormalEquations, RefineConsequentsTrainingFitNeverFallsAsTheRidgeShrinks) {
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

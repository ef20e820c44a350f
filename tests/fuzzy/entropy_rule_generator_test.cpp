// The entropy criterion of docs/identifier.md §4.

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "fuzzy/fuzzy_model.hpp"

namespace odonata::fuzzy {
namespace {

Eigen::MatrixXd FixedData(int samples, int inputs) {
  std::mt19937 rng(123);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Eigen::MatrixXd x(samples, inputs);
  for (int r = 0; r < samples; ++r)
    for (int i = 0; i < inputs; ++i) x(r, i) = u(rng);
  return x;
}

int GrowOnly(double threshold, const Eigen::MatrixXd& x, int cap = 1000) {
  // Structure only (no tuning) so the count depends on H̄ alone.
  FuzzyModelConfig cfg;
  cfg.inputs = static_cast<int>(x.cols());
  cfg.entropy.threshold = threshold;
  cfg.entropy.max_rules = cap;
  cfg.rates.centre = cfg.rates.sigma = 0.0;
  FuzzyModel m(cfg);
  for (Eigen::Index r = 0; r < x.rows(); ++r) m.Learn(x.row(r).transpose(), x(r, 0));
  return m.rules();
}

TEST(EntropyRuleGenerator, EntropyOfAFullyFiringRuleIs0531) {
  EXPECT_NEAR(EntropyRuleGenerator::FiringEntropy(1.0), 0.5307, 1e-4);
  // −D log₂ D with D = exp(−F), written out, at a few points.
  for (double f : {1e-3, 0.1, 0.5, 0.9}) {
    const double d = std::exp(-f);
    EXPECT_NEAR(EntropyRuleGenerator::FiringEntropy(f), -d * std::log2(d), 1e-12);
  }
}

TEST(EntropyRuleGenerator, ThresholdTableOfTheReference) {
  // docs/identifier.md §4: H̄ = 0.05 ⇔ F ≈ 0.036 ⇔ distance ≈ 2.58 σ (one input).
  const double f = std::exp(-0.5 * 2.58 * 2.58);
  EXPECT_NEAR(EntropyRuleGenerator::FiringEntropy(f), 0.05, 0.002);
}

TEST(EntropyRuleGenerator, RuleCountNeverFallsAsThresholdRises) {
  const Eigen::MatrixXd x = FixedData(600, 2);
  int previous = 0;
  for (double h : {0.001, 0.002, 0.007, 0.01, 0.05, 0.1, 0.178, 0.25, 0.35, 0.45, 0.52}) {
    const int rules = GrowOnly(h, x);
    EXPECT_GE(rules, previous) << "H̄ = " << h;
    previous = rules;
  }
  EXPECT_GT(previous, GrowOnly(0.001, x));
}

TEST(EntropyRuleGenerator, FirstSampleAlwaysCreatesARule) {
  for (double h : {0.0, 1e-9, 0.05, 0.5}) {
    FuzzyModelConfig cfg;
    cfg.inputs = 2;
    cfg.entropy.threshold = h;
    FuzzyModel m(cfg);
    const auto r = m.Learn(Eigen::Vector2d(0.3, -0.2), 1.0);
    EXPECT_TRUE(r.rule_added);
    EXPECT_EQ(m.rules(), 1);
  }
}

TEST(EntropyRuleGenerator, CapHolds) {
  const Eigen::MatrixXd x = FixedData(2000, 3);
  for (int cap : {1, 5, 17}) EXPECT_EQ(GrowOnly(0.52, x, cap), cap);
}

TEST(EntropyRuleGenerator, NewWidthFollowsTheVectorDistanceToTheNearestCentre) {
  EntropyRuleConfig cfg;
  cfg.kappa = 0.5;
  cfg.sigma_min = 0.01;
  GaussianRuleBase rb(2, 4);
  EXPECT_DOUBLE_EQ(EntropyRuleGenerator::NewWidths(cfg, rb, Eigen::Vector2d(0, 0))(0),
                   cfg.sigma_init);
  rb.AddRule(Eigen::Vector2d(0, 0), Eigen::Vector2d(0.3, 0.3));
  rb.AddRule(Eigen::Vector2d(2, 2), Eigen::Vector2d(0.3, 0.3));
  // One coordinate almost on the nearest centre must not collapse that input's width: both
  // inputs get κ · RMS distance = 0.5 · sqrt((0.4² + 0.001²) / 2).
  const Eigen::VectorXd s = EntropyRuleGenerator::NewWidths(cfg, rb, Eigen::Vector2d(0.4, -0.001));
  const double expected = 0.5 * std::sqrt((0.16 + 1e-6) / 2);
  EXPECT_DOUBLE_EQ(s(0), expected);
  EXPECT_DOUBLE_EQ(s(1), expected);
  cfg.sigma_min = 0.2;
  EXPECT_DOUBLE_EQ(EntropyRuleGenerator::NewWidths(cfg, rb, Eigen::Vector2d(0.4, -0.001))(1), 0.2);
}

TEST(EntropyRuleGenerator, WidthsDoNotCollapseToTheFloor) {
  // The old per-input rule (κ · nearest distance in each coordinate) put the median width at the
  // floor on 4-input data; the vector distance keeps it well above.
  const Eigen::MatrixXd x = FixedData(2000, 4);
  FuzzyModelConfig cfg;
  cfg.inputs = 4;
  cfg.entropy.threshold = 0.5;
  cfg.entropy.sigma_min = 0.02;
  cfg.rates.centre = cfg.rates.sigma = 0.0;
  FuzzyModel m(cfg);
  for (Eigen::Index r = 0; r < x.rows(); ++r) m.Learn(x.row(r).transpose(), 0.0);
  ASSERT_GT(m.rules(), 10);
  std::vector<double> widths;
  for (int j = 1; j < m.rules(); ++j) widths.push_back(m.rule_base().sigma(j, 0));
  std::nth_element(widths.begin(), widths.begin() + widths.size() / 2, widths.end());
  EXPECT_GT(widths[widths.size() / 2], 5 * cfg.entropy.sigma_min);
}

TEST(EntropyRuleGenerator, OneThresholdMeansOneRadiusForAnyInputCount) {
  // A sample 1.5 widths from the only rule in every input has the same entropy for N = 1, 3, 6.
  EntropyRuleConfig cfg;
  double first = -1.0;
  for (int n : {1, 3, 6}) {
    GaussianRuleBase rb(n, 1);
    rb.AddRule(Eigen::VectorXd::Zero(n), Eigen::VectorXd::Constant(n, 0.4));
    const Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 1.5 * 0.4);
    Inference inf;
    rb.Evaluate(x, &inf);
    const double h = EntropyRuleGenerator::MaxEntropy(cfg, rb, inf, x);
    if (first < 0) first = h;
    EXPECT_NEAR(h, first, 1e-6) << "N = " << n;
  }
  EXPECT_NEAR(first, EntropyRuleGenerator::FiringEntropy(std::exp(-0.5 * 1.5 * 1.5)), 1e-5);
}

TEST(EntropyRuleGenerator, TheCoreRejectsAThresholdOutOfRange) {
  for (double h : {-0.01, 0.54, std::nan("")}) {
    FuzzyModelConfig cfg;
    cfg.entropy.threshold = h;
    EXPECT_FALSE(cfg.Problems().empty()) << h;
    EXPECT_THROW(FuzzyModel{cfg}, std::invalid_argument) << h;
  }
  FuzzyModel m(FuzzyModelConfig{});
  EXPECT_THROW(m.set_entropy_threshold(0.6), std::invalid_argument);
  EXPECT_NO_THROW(m.set_entropy_threshold(kMaxRuleEntropy));
  EXPECT_NO_THROW(m.set_entropy_threshold(0.0));
  FuzzyModelConfig huge;
  huge.entropy.max_rules = 2000000000;
  EXPECT_THROW(FuzzyModel{huge}, std::invalid_argument) << "refused before any allocation";
}

TEST(EntropyRuleGenerator, PerInputMeasureLetsCloseInputsMaskNovelty) {
  // A sample three widths from the rule in one input and on its centre in the other two: the
  // per-input measure sees two well-covered inputs and reports more entropy (less novelty).
  GaussianRuleBase rb(3, 1);
  rb.AddRule(Eigen::Vector3d::Zero(), Eigen::Vector3d::Constant(0.2));
  const Eigen::Vector3d x(0.6, 0.0, 0.0);
  Inference inf;
  rb.Evaluate(x, &inf);
  EntropyRuleConfig firing, per_input;
  per_input.measure = EntropyMeasure::kPerInput;
  const double h_firing = EntropyRuleGenerator::MaxEntropy(firing, rb, inf, x);
  const double h_per_input = EntropyRuleGenerator::MaxEntropy(per_input, rb, inf, x);
  EXPECT_NEAR(h_firing, EntropyRuleGenerator::FiringEntropy(std::exp(-1.5)), 1e-5);
  EXPECT_GT(h_per_input, h_firing + 0.05);
}

}  // namespace
}  // namespace odonata::fuzzy

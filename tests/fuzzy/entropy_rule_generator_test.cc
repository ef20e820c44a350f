// The entropy criterion of identifier.md §3.

#include <cmath>
#include <random>

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
  // identifier.md §3: H̄ = 0.05 ⇔ F ≈ 0.036 ⇔ distance ≈ 2.58 σ (one input).
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

TEST(EntropyRuleGenerator, NewWidthFollowsNearestCentre) {
  EntropyRuleConfig cfg;
  cfg.kappa = 0.5;
  cfg.sigma_min = 0.01;
  GaussianRuleBase rb(2, 4);
  EntropyRuleGenerator gen(cfg);
  EXPECT_DOUBLE_EQ(gen.NewWidths(rb, Eigen::Vector2d(0, 0))(0), cfg.sigma_init);
  rb.AddRule(Eigen::Vector2d(0, 0), Eigen::Vector2d(0.3, 0.3));
  const Eigen::VectorXd s = gen.NewWidths(rb, Eigen::Vector2d(0.4, -0.001));
  EXPECT_DOUBLE_EQ(s(0), 0.2);
  EXPECT_DOUBLE_EQ(s(1), 0.01);  // floored at σ_min
}

TEST(EntropyRuleGenerator, PerInputMeasureGrowsFewerRules) {
  const Eigen::MatrixXd x = FixedData(600, 3);
  FuzzyModelConfig cfg;
  cfg.inputs = 3;
  cfg.entropy.threshold = 0.3;
  cfg.entropy.max_rules = 1000;
  cfg.rates.centre = cfg.rates.sigma = 0.0;
  FuzzyModel product(cfg);
  cfg.entropy.measure = EntropyMeasure::kPerInput;
  // The per-input sum ranges over [0, 3 × 0.531]: scale H̄ by the input count to compare.
  cfg.entropy.threshold = 0.9;
  FuzzyModel per_input(cfg);
  for (Eigen::Index r = 0; r < x.rows(); ++r) {
    product.Learn(x.row(r).transpose(), 0.0);
    per_input.Learn(x.row(r).transpose(), 0.0);
  }
  EXPECT_GT(per_input.rules(), 0);
  EXPECT_LT(per_input.rules(), product.rules());
}

}  // namespace
}  // namespace odonata::fuzzy

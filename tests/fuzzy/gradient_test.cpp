// Every analytic gradient of docs/identifier.md §3 against central finite differences.

#include <random>

#include <gtest/gtest.h>

#include "fuzzy/fuzzy_model.hpp"

namespace odonata::fuzzy {
namespace {

double Loss(const FuzzyModel& m, const Eigen::VectorXd& x, double y) {
  const double e = m.Predict(x) - y;
  return 0.5 * e * e;
}

/// Builds a model with `rules` random rules (seeded) and non-trivial s_j and consequents.
FuzzyModel RandomModel(ConsequentKind kind, int inputs, int rules, unsigned seed) {
  FuzzyModelConfig cfg;
  cfg.inputs = inputs;
  cfg.consequent = kind;
  cfg.entropy.max_rules = rules;
  FuzzyModel m(cfg);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> w(0.3, 0.9);
  for (int j = 0; j < rules; ++j) {
    Eigen::VectorXd c(inputs), s(inputs);
    for (int i = 0; i < inputs; ++i) {
      c(i) = u(rng);
      s(i) = w(rng);
    }
    m.mutable_consequent().AddRule(c, u(rng), Eigen::ArrayXd::Zero(j));
    m.mutable_rule_base().AddRule(c, s, 0.5 + 0.5 * w(rng));
  }
  // Perturb every consequent parameter so no gradient vanishes by symmetry.
  Eigen::VectorXd p = m.consequent().Parameters();
  for (Eigen::Index k = 0; k < p.size(); ++k) p(k) += 0.3 * u(rng);
  m.mutable_consequent().SetParameters(p);
  return m;
}

void ExpectClose(double analytic, double numeric, const std::string& what) {
  // Relative error, with a floor so a gradient that is exactly zero (every premise gradient
  // when R = 1, since y_j − ŷ = 0) is compared in absolute terms against rounding noise.
  const double scale = std::max({1e-3, std::abs(analytic), std::abs(numeric)});
  EXPECT_LT(std::abs(analytic - numeric) / scale, 1e-6)
      << what << ": analytic " << analytic << " numeric " << numeric;
}

class GradientTest : public ::testing::TestWithParam<std::tuple<ConsequentKind, int>> {};

TEST_P(GradientTest, MatchesCentralDifferences) {
  const auto [kind, rules] = GetParam();
  const int inputs = 3;
  FuzzyModel m = RandomModel(kind, inputs, rules, 42u + static_cast<unsigned>(rules));
  Eigen::VectorXd x(inputs);
  x << 0.2, -0.4, 0.7;
  const double y = 0.35;
  const Gradients g = m.ComputeGradients(x, y);
  auto numeric = [&](auto get, auto set) {
    const double z = get();
    const double h = 1e-6 * std::max(1.0, std::abs(z));
    set(z + h);
    const double lp = Loss(m, x, y);
    set(z - h);
    const double lm = Loss(m, x, y);
    set(z);
    return (lp - lm) / (2 * h);
  };
  auto& rb = m.mutable_rule_base();
  for (int j = 0; j < rules; ++j) {
    for (int i = 0; i < inputs; ++i) {
      ExpectClose(
          g.centres(j, i),
          numeric([&] { return rb.centre(j, i); }, [&](double v) { rb.set_centre(j, i, v); }),
          "dJ/dc");
      ExpectClose(g.sigmas(j, i),
                  numeric([&] { return rb.sigma(j, i); }, [&](double v) { rb.set_sigma(j, i, v); }),
                  "dJ/dsigma");
    }
    ExpectClose(
        g.output_widths(j),
        numeric([&] { return rb.output_width(j); }, [&](double v) { rb.set_output_width(j, v); }),
        "dJ/ds");
  }
  Eigen::VectorXd p = m.consequent().Parameters();
  ASSERT_EQ(p.size(), g.consequents.size());
  for (Eigen::Index k = 0; k < p.size(); ++k) {
    ExpectClose(g.consequents(k),
                numeric([&] { return p(k); },
                        [&](double v) {
                          p(k) = v;
                          m.mutable_consequent().SetParameters(p);
                        }),
                "dJ/dconsequent");
  }
}

INSTANTIATE_TEST_SUITE_P(AllKindsAndSizes, GradientTest,
                         ::testing::Combine(::testing::Values(ConsequentKind::kSingleton,
                                                              ConsequentKind::kLinear),
                                            ::testing::Values(1, 2, 7)));

TEST(GradientStep, LearnStepsAlongTheCheckedGradient) {
  // Learn() and ComputeGradients() share one kernel: one premise step with small unclipped rates
  // moves every centre and width by exactly −α ∂J/∂θ, the gradient checked above.
  for (auto kind : {ConsequentKind::kSingleton, ConsequentKind::kLinear}) {
    FuzzyModel m = RandomModel(kind, 3, 4, 99u);
    FuzzyModelConfig cfg = m.config();
    Eigen::VectorXd x(3);
    x << 0.25, -0.1, 0.4;
    const double y = -0.3;
    const Gradients g = m.ComputeGradients(x, y);
    const auto& rb = m.rule_base();
    Eigen::ArrayXXd c0(4, 3), s0(4, 3);
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        c0(j, i) = rb.centre(j, i);
        s0(j, i) = rb.sigma(j, i);
      }
    const double alpha = 1e-3;
    m.Learn(x, y, LearnMode::kTunePremises, alpha / cfg.rates.centre);
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 3; ++i) {
        EXPECT_NEAR(rb.centre(j, i) - c0(j, i), -alpha * g.centres(j, i), 1e-15);
        EXPECT_NEAR(rb.sigma(j, i) - s0(j, i),
                    -alpha * cfg.rates.sigma / cfg.rates.centre * g.sigmas(j, i), 1e-15);
      }
    // The batch gradient the offline trainer uses is the same kernel, summed.
    Eigen::ArrayXXd gc = Eigen::ArrayXXd::Zero(4, 3), gs = Eigen::ArrayXXd::Zero(4, 3);
    const FuzzyModel fresh = RandomModel(kind, 3, 4, 99u);
    fresh.AccumulatePremiseGradient(x, y, &gc, &gs);
    fresh.AccumulatePremiseGradient(x, y, &gc, &gs);
    EXPECT_LT((gc - 2 * g.centres).abs().maxCoeff(), 1e-15);
    EXPECT_LT((gs - 2 * g.sigmas).abs().maxCoeff(), 1e-15);
  }
}

TEST(GradientStep, ReducesTheLossOnTheSameSample) {
  FuzzyModel m = RandomModel(ConsequentKind::kSingleton, 2, 5, 7u);
  Eigen::VectorXd x(2);
  x << 0.1, 0.3;
  const double before = Loss(m, x, 0.8);
  m.Learn(x, 0.8, LearnMode::kTune);
  EXPECT_LT(Loss(m, x, 0.8), before);
}

// The offline premise step takes its gradient at the firings the least-squares pass kept: the
// same sums, bit for bit, as evaluating them again (sysid/estimation/narx_training.cpp).
TEST(PremiseGradient, AtKeptFiringsEqualsEvaluatingThemBitForBit) {
  for (const auto kind : {ConsequentKind::kLinear, ConsequentKind::kSingleton}) {
    FuzzyModel m = RandomModel(kind, 3, 9, 21u);
    std::mt19937 rng(4);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    Eigen::MatrixXd xs(300, 3);
    Eigen::VectorXd ys(300);
    for (int k = 0; k < 300; ++k) {
      for (int i = 0; i < 3; ++i) xs(k, i) = u(rng);
      ys(k) = std::sin(2 * xs(k, 0)) + xs(k, 1) * xs(k, 2);
    }
    Eigen::ArrayXXd firings;
    double squares = 0.0;
    ASSERT_TRUE(m.RefineConsequents(xs, ys, 1e-10, 0.0, &squares, &firings));
    ASSERT_EQ(firings.rows(), 300);
    ASSERT_EQ(firings.cols(), 9);
    Eigen::ArrayXXd gc = Eigen::ArrayXXd::Zero(9, 3), gs = gc, kc = gc, ks = gc;
    double loss = 0.0;
    for (int k = 0; k < 300; ++k) {
      m.AccumulatePremiseGradient(xs.row(k).transpose(), ys(k), &gc, &gs);
      m.AccumulatePremiseGradientAt(xs.row(k).transpose(), firings.row(k).transpose(), ys(k), &kc,
                                    &ks);
      loss += std::pow(m.Predict(xs.row(k).transpose()) - ys(k), 2);
    }
    EXPECT_TRUE((gc == kc).all());
    EXPECT_TRUE((gs == ks).all());
    // The solve's own residual is the loss its model leaves.
    EXPECT_NEAR(squares, loss, 1e-9 * loss);
  }
}

}  // namespace
}  // namespace odonata::fuzzy

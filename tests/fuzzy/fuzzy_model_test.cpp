// Inference, learning, determinism and persistence of one fuzzy model.

#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/QR>
#include <nlohmann/json.hpp>

#include "fuzzy/fuzzy_model.hpp"

namespace odonata::fuzzy {
namespace {

FuzzyModel Trained(ConsequentKind kind) {
  FuzzyModelConfig cfg;
  cfg.inputs = 2;
  cfg.consequent = kind;
  cfg.entropy.threshold = 0.52;
  cfg.entropy.kappa = 0.3;
  cfg.rates.output_width = 0.01;
  FuzzyModel m(cfg);
  for (int k = 0; k < 3000; ++k) {
    const double a = std::sin(0.013 * k), b = std::cos(0.007 * k);
    m.Learn(Eigen::Vector2d(a, b), a * b + 0.5 * a);
  }
  return m;
}

TEST(FuzzyModel, SingleRuleOutputsItsConsequentEverywhere) {
  FuzzyModelConfig cfg;
  cfg.inputs = 1;
  FuzzyModel m(cfg);
  m.Learn(Eigen::VectorXd::Constant(1, 0.0), 0.7, LearnMode::kGrowAndTune);
  const double b = m.Predict(Eigen::VectorXd::Constant(1, 0.0));
  // Far away the firing strength underflows, but the shifted evaluation still normalises.
  EXPECT_DOUBLE_EQ(m.Predict(Eigen::VectorXd::Constant(1, 1e3)), b);
  EXPECT_TRUE(std::isfinite(m.Predict(Eigen::VectorXd::Constant(1, 1e150))));
}

TEST(FuzzyModel, CentreAverageOfTwoRules) {
  FuzzyModelConfig cfg;
  cfg.inputs = 1;
  cfg.rates.centre = cfg.rates.sigma = 0.0;
  FuzzyModel m(cfg);
  m.mutable_consequent().AddRule(Eigen::VectorXd::Constant(1, -1), 1.0, Eigen::ArrayXd());
  m.mutable_rule_base().AddRule(Eigen::VectorXd::Constant(1, -1), Eigen::VectorXd::Constant(1, 1));
  m.mutable_consequent().AddRule(Eigen::VectorXd::Constant(1, 1), 3.0, Eigen::ArrayXd::Ones(1));
  m.mutable_rule_base().AddRule(Eigen::VectorXd::Constant(1, 1), Eigen::VectorXd::Constant(1, 1));
  EXPECT_NEAR(m.Predict(Eigen::VectorXd::Constant(1, 0.0)), 2.0, 1e-12);
  const double f1 = std::exp(-0.5 * 0.25 / (1 + kEpsilon)),
               f2 = std::exp(-0.5 * 2.25 / (1 + kEpsilon));
  EXPECT_NEAR(m.Predict(Eigen::VectorXd::Constant(1, -0.5)), (f1 * 1 + f2 * 3) / (f1 + f2), 1e-12);
}

TEST(FuzzyModel, LearnsASmoothSurface) {
  for (auto kind : {ConsequentKind::kSingleton, ConsequentKind::kLinear}) {
    const FuzzyModel m = Trained(kind);
    double se = 0, ss = 0;
    for (int k = 0; k < 500; ++k) {
      const double a = std::sin(0.031 * k), b = std::cos(0.017 * k);
      const double y = a * b + 0.5 * a;
      se += std::pow(m.Predict(Eigen::Vector2d(a, b)) - y, 2);
      ss += y * y;
    }
    // One online pass, no least squares: the singleton model is the coarser of the two.
    const double bound = kind == ConsequentKind::kSingleton ? 0.2 : 0.1;
    EXPECT_LT(std::sqrt(se / ss), bound) << ToString(kind);
  }
}

TEST(FuzzyModel, SameDataSameModelBitForBit) {
  for (auto kind : {ConsequentKind::kSingleton, ConsequentKind::kLinear}) {
    EXPECT_EQ(Trained(kind).ToJson().dump(), Trained(kind).ToJson().dump());
  }
}

TEST(FuzzyModel, JsonRoundTripGivesIdenticalPredictionsAndLearning) {
  for (auto kind : {ConsequentKind::kSingleton, ConsequentKind::kLinear}) {
    FuzzyModel a = Trained(kind);
    FuzzyModel b = FuzzyModel::FromJson(nlohmann::json::parse(a.ToJson().dump()));
    for (int k = 0; k < 200; ++k) {
      const Eigen::Vector2d x(std::sin(0.1 * k), std::cos(0.05 * k));
      ASSERT_EQ(a.Predict(x), b.Predict(x));  // bit for bit, not near
      a.Learn(x, 0.3);
      b.Learn(x, 0.3);
    }
    EXPECT_EQ(a.ToJson().dump(), b.ToJson().dump()) << "learning resumed identically";
  }
}

TEST(FuzzyModel, FromJsonRejectsMalformedContent) {
  nlohmann::json j = Trained(ConsequentKind::kSingleton).ToJson();
  nlohmann::json bad = j;
  bad["rules"][0]["sigma"][0] = -1.0;
  EXPECT_THROW(FuzzyModel::FromJson(bad), std::runtime_error);
  bad = j;
  bad["rules"][0]["centre"].erase(0);
  EXPECT_THROW(FuzzyModel::FromJson(bad), std::runtime_error);
  bad = j;
  bad.erase("entropy");
  EXPECT_THROW(FuzzyModel::FromJson(bad), std::runtime_error);
  bad = j;
  bad["consequent"]["kind"] = "cubic";
  EXPECT_THROW(FuzzyModel::FromJson(bad), std::exception);
}

TEST(FuzzyModel, RefineConsequentsSolvesTheLeastSquaresProblem) {
  // With fixed antecedents the least-squares consequents must beat any online estimate.
  FuzzyModel m = Trained(ConsequentKind::kLinear);
  Eigen::MatrixXd x(400, 2);
  Eigen::VectorXd y(400);
  for (int k = 0; k < 400; ++k) {
    x.row(k) << std::sin(0.021 * k), std::cos(0.011 * k);
    y(k) = x(k, 0) * x(k, 1) + 0.5 * x(k, 0);
  }
  auto sse = [&] {
    double s = 0;
    for (int k = 0; k < 400; ++k) s += std::pow(m.Predict(x.row(k).transpose()) - y(k), 2);
    return s;
  };
  const double before = sse();
  m.RefineConsequents(x, y, 1e-12);
  EXPECT_LT(sse(), before);
}

// The deviation ridge pulls every rule toward one global linear model: none makes no difference
// from plain least squares, a huge one leaves every rule with the same consequent — the global
// least-squares line, ARX — and the training error grows with it.
TEST(FuzzyModel, TheDeviationRidgeShrinksRulesTowardOneGlobalLinearModel) {
  Eigen::MatrixXd x(400, 2);
  Eigen::VectorXd y(400);
  for (int k = 0; k < 400; ++k) {
    x.row(k) << std::sin(0.021 * k), std::cos(0.011 * k);
    y(k) = x(k, 0) * x(k, 1) + 0.5 * x(k, 0);
  }
  auto sse = [&](const FuzzyModel& m) {
    double s = 0;
    for (int k = 0; k < 400; ++k) s += std::pow(m.Predict(x.row(k).transpose()) - y(k), 2);
    return s;
  };
  FuzzyModel plain = Trained(ConsequentKind::kLinear), tiny = plain, huge = plain;
  ASSERT_GE(plain.rules(), 3);
  ASSERT_TRUE(plain.RefineConsequents(x, y, 1e-12));
  ASSERT_TRUE(tiny.RefineConsequents(x, y, 1e-12, 1e-12));
  ASSERT_TRUE(huge.RefineConsequents(x, y, 1e-12, 1e8));
  EXPECT_NEAR(sse(tiny), sse(plain), 1e-6 * (1 + sse(plain)));
  EXPECT_GT(sse(huge), 2 * sse(plain));
  const Eigen::VectorXd p = huge.consequent().Parameters();
  const int w = 3;  // a_0 and one slope per input
  for (int j = 1; j < huge.rules(); ++j)
    EXPECT_LT((p.segment(j * w, w) - p.head(w)).norm(), 1e-4) << "rule " << j;
  // The shared consequent is the least-squares line through all the data.
  Eigen::MatrixXd a(400, 3);
  a << Eigen::VectorXd::Ones(400), x;
  const Eigen::VectorXd line = a.colPivHouseholderQr().solve(y);
  EXPECT_LT((p.head(w) - line).norm(), 1e-3);
}

// A rule that fires on fewer effective samples than its consequent has parameters cannot be
// estimated: PruneUnsupported removes it, keeps the rules the data covers, and never the last.
TEST(FuzzyModel, PruneUnsupportedRemovesARuleTheDataDoesNotCover) {
  FuzzyModelConfig cfg;
  cfg.inputs = 1;
  cfg.entropy.threshold = 0.5;
  cfg.entropy.kappa = 0.5;
  cfg.entropy.sigma_max = 0.4;
  FuzzyModel m(cfg);
  // Rules at −0.6 and 0.6 (the data), then one at 3 (a single outlier).
  for (const double v : {-0.6, 0.6, 3.0})
    m.Learn(Eigen::VectorXd::Constant(1, v), v, LearnMode::kGrowAndTune);
  ASSERT_EQ(m.rules(), 3);
  Eigen::MatrixXd x(201, 1);
  for (int k = 0; k < 200; ++k) x(k, 0) = -0.8 + 1.6 * k / 199.0;
  x(200, 0) = 3.0;
  FuzzyModel none = m, loose = m;
  EXPECT_EQ(none.PruneUnsupported(x, 0.0), 0);
  EXPECT_EQ(none.rules(), 3);
  // The outlier's rule carries about one sample; a linear consequent has two parameters.
  EXPECT_EQ(m.PruneUnsupported(x, 1.0), 1);
  ASSERT_EQ(m.rules(), 2);
  EXPECT_NEAR(m.rule_base().centre(0, 0), -0.6, 0.2);
  EXPECT_NEAR(m.rule_base().centre(1, 0), 0.6, 0.2);
  EXPECT_EQ(m.rules_pruned(), 1);
  // A demand no rule meets still leaves the best-supported one.
  EXPECT_EQ(loose.PruneUnsupported(x, 1e6), 2);
  EXPECT_EQ(loose.rules(), 1);
}

TEST(FuzzyModel, PruningKeepsALongRunBelowTheCapAndKeepsLearning) {
  // A slowly drifting operating point visits new regions for ever: without pruning the rule base
  // fills up and its structure freezes; with pruning old, unused rules make room.
  FuzzyModelConfig cfg;
  cfg.inputs = 1;
  cfg.entropy.threshold = 0.45;
  cfg.entropy.kappa = 0.5;
  cfg.entropy.sigma_init = 0.1;
  cfg.entropy.sigma_min = 0.05;
  cfg.entropy.sigma_max = 0.15;
  cfg.entropy.max_rules = 10;
  cfg.entropy.prune_utility = 0.01;
  cfg.entropy.prune_min_age = 200;
  FuzzyModel pruned(cfg);
  cfg.entropy.prune_utility = 0.0;
  FuzzyModel capped(cfg);
  double late_error_pruned = 0, late_error_capped = 0;
  for (int k = 0; k < 40000; ++k) {
    const double centre = -1.0 + 2.0 * k / 40000.0 * 3.0;  // drifts from −1 to 5 (scaled units)
    const double x = centre + 0.1 * std::sin(0.37 * k);
    const double y = std::sin(2 * x);
    const auto a = pruned.Learn(Eigen::VectorXd::Constant(1, x), y);
    const auto b = capped.Learn(Eigen::VectorXd::Constant(1, x), y);
    if (k >= 36000) {
      late_error_pruned += a.error * a.error;
      late_error_capped += b.error * b.error;
    }
    ASSERT_LE(pruned.rules(), 10);
  }
  EXPECT_GT(pruned.rules_pruned(), 0);
  EXPECT_EQ(capped.rules(), 10);
  EXPECT_LT(late_error_pruned, 0.25 * late_error_capped);
}

TEST(FuzzyModel, ForgettingTracksAChangedPlant) {
  FuzzyModelConfig cfg;
  cfg.inputs = 1;
  cfg.consequent = ConsequentKind::kLinear;
  FuzzyModel remember(cfg);
  cfg.forgetting = 0.99;
  FuzzyModel forget(cfg);
  double err_remember = 0, err_forget = 0;
  for (int k = 0; k < 6000; ++k) {
    const double x = std::sin(0.05 * k);
    const double gain = k < 3000 ? 1.0 : 0.7;  // a wing loses 30 % of its authority
    const auto a = remember.Learn(Eigen::VectorXd::Constant(1, x), gain * x);
    const auto b = forget.Learn(Eigen::VectorXd::Constant(1, x), gain * x);
    if (k >= 3500) {
      err_remember += a.error * a.error;
      err_forget += b.error * b.error;
    }
  }
  EXPECT_LT(err_forget, 0.1 * err_remember);
  // Forgetting amplifies any skew part of P, so P must have stayed symmetric bit for bit.
  const auto cov = forget.ToJson()["consequent"]["covariances"];
  for (const auto& c : cov) {
    const auto v = c.get<std::vector<double>>();
    const int n = static_cast<int>(std::lround(std::sqrt(double(v.size()))));
    for (int a = 0; a < n; ++a)
      for (int b = 0; b < n; ++b) EXPECT_EQ(v[a + b * n], v[b + a * n]);
  }
  EXPECT_THROW(forget.set_forgetting(0.0), std::invalid_argument);
  EXPECT_THROW(forget.set_forgetting(1.01), std::invalid_argument);
  forget.set_forgetting(0.95);
  EXPECT_DOUBLE_EQ(FuzzyModel::FromJson(forget.ToJson()).config().forgetting, 0.95);
}

}  // namespace
}  // namespace odonata::fuzzy

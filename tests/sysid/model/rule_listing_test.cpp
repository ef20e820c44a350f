#include <gtest/gtest.h>

#include "fuzzy/linear_consequent.hpp"
#include "sysid/model/rule_listing.hpp"

namespace odonata::sysid {
namespace {

TEST(RuleListing, LabelsFollowTheInputRange) {
  EXPECT_EQ(LinguisticLabel(-0.9), "very low");
  EXPECT_EQ(LinguisticLabel(-0.3), "low");
  EXPECT_EQ(LinguisticLabel(0.0), "medium");
  EXPECT_EQ(LinguisticLabel(0.5), "high");
  EXPECT_EQ(LinguisticLabel(0.95), "very high");
  // Beyond the declared range is still that end of the data.
  EXPECT_EQ(LinguisticLabel(1.4), "very high");
  EXPECT_EQ(LinguisticLabel(-1.4), "very low");
}

NarxModel OneRuleModel(fuzzy::ConsequentKind kind) {
  RegressorSpec spec{0, 1, 1, {"y"}, {"u"}};
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  NarxModel m(spec, cfg);
  Scaling s;
  s.regressor_mid = Eigen::VectorXd::Constant(1, 1.0);
  s.regressor_half = Eigen::VectorXd::Constant(1, 2.0);
  s.output_mean = Eigen::VectorXd::Constant(1, 10.0);
  s.output_std = Eigen::VectorXd::Constant(1, 2.0);
  m.SetScaling(s);
  // Raw u = 2.6 is scaled 0.8: "very high"; target raw 11 is scaled 0.5.
  m.Learn(Eigen::VectorXd::Constant(1, 2.6), Eigen::VectorXd::Constant(1, 11.0),
          fuzzy::LearnMode::kGrowAndTune);
  return m;
}

TEST(RuleListing, SingletonSentenceInRawUnits) {
  NarxModel m = OneRuleModel(fuzzy::ConsequentKind::kSingleton);
  auto lines = DescribeRules(m, 0);
  ASSERT_EQ(lines.size(), 1u);
  // One rule fires fully everywhere: no IF, the constant it is.
  EXPECT_EQ(lines[0], "y(k+1) = 11 (one rule: a constant)") << lines[0];
  // A second rule: sentences.
  m.Learn(Eigen::VectorXd::Constant(1, -0.6), Eigen::VectorXd::Constant(1, 9.0),
          fuzzy::LearnMode::kGrowAndTune);
  lines = DescribeRules(m, 0);
  ASSERT_EQ(lines.size(), 2u);
  EXPECT_EQ(lines[0].rfind("IF u(k) is very high (≈2.6 ±", 0), 0u) << lines[0];
  EXPECT_NE(lines[0].find(" THEN y(k+1) is ≈11"), std::string::npos) << lines[0];
}

TEST(RuleListing, LinearConsequentExpandsToRawCoefficients) {
  NarxModel m = OneRuleModel(fuzzy::ConsequentKind::kLinear);
  // Scaled θ = [0.5, 0.25] ⇒ y = 10 + 2 (0.5 + 0.25 (u − 1)/2) = 10.75 + 0.25 u.
  m.mutable_model(0).mutable_consequent().SetParameters(Eigen::Vector2d(0.5, 0.25));
  const auto lines = DescribeRules(m, 0);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_EQ(lines[0], "y(k+1) = 10.8 + 0.25·u(k) (one rule: a linear model, as ARX)") << lines[0];
  // The sentence is the model: check it against a prediction.
  EXPECT_NEAR(m.Predict(Eigen::VectorXd::Constant(1, 3.0))(0), 10.75 + 0.25 * 3.0, 1e-12);
}

}  // namespace
}  // namespace odonata::sysid

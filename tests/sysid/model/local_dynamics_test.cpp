// Each rule's dynamics as a control engineer reads them (issue 49 point 2): poles, stability,
// time constants, damping and steady-state gains of the linear local models, from raw units.
#include "sysid/model/local_dynamics.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <nlohmann/json.hpp>

#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/rule_listing.hpp"

namespace odonata::sysid {
namespace {

// y(t) = 0.1 + 1.5 y(t−1) − 0.7 y(t−2) + 0.5 u(t−1) + 0.2 u(t−2): poles 0.75 ± 0.37081i
// (|p|² = 0.7), steady-state gain 0.7 / 0.2 = 3.5, at rest 0.1 / 0.2 = 0.5.
RegressorSpec Spec() {
  RegressorSpec s;
  s.output_lags = 2;
  s.input_lags = 2;
  s.delay = 1;
  s.outputs = {"pitch"};
  s.inputs = {"servo"};
  return s;
}

Series Plant(int samples) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  Series s;
  s.outputs = Eigen::MatrixXd::Zero(samples, 1);
  s.inputs = Eigen::MatrixXd::Zero(samples, 1);
  for (int t = 0; t < samples; ++t) s.inputs(t, 0) = level(rng);
  for (int t = 2; t < samples; ++t)
    s.outputs(t, 0) = 0.1 + 1.5 * s.outputs(t - 1, 0) - 0.7 * s.outputs(t - 2, 0) +
                      0.5 * s.inputs(t - 1, 0) + 0.2 * s.inputs(t - 2, 0);
  return s;
}

RawLinearModel Exact() {
  RawLinearModel m;
  m.constant = 0.1;
  m.coefficients = Eigen::Vector4d(1.5, -0.7, 0.5, 0.2);
  return m;
}

TEST(LocalDynamics, PolesGainsTimeConstantsAndDampingOfAKnownModel) {
  const LocalDynamics d = AnalyseDynamics(Spec(), 0, Exact(), 0.01);
  ASSERT_EQ(d.poles.size(), 2u);
  EXPECT_NEAR(d.poles[0].real(), 0.75, 1e-12);
  EXPECT_NEAR(std::abs(d.poles[0].imag()), std::sqrt(0.7 - 0.75 * 0.75), 1e-12);
  EXPECT_NEAR(d.poles[1].imag(), -d.poles[0].imag(), 1e-12);
  EXPECT_TRUE(d.stable);
  EXPECT_NEAR(d.time_constants[0], -0.01 / std::log(std::sqrt(0.7)), 1e-12);
  EXPECT_GT(d.damping[0], 0.0);
  EXPECT_LT(d.damping[0], 1.0);
  ASSERT_EQ(d.dc_gain.size(), 1u);
  EXPECT_EQ(d.dc_gain[0].first, "servo");
  EXPECT_NEAR(d.dc_gain[0].second, 3.5, 1e-12);
  EXPECT_NEAR(d.equilibrium, 0.5, 1e-12);
  const nlohmann::json j = ToJson(d, 0.01);
  EXPECT_NEAR(j["dc_gain"]["servo"].get<double>(), 3.5, 1e-12);
  EXPECT_EQ(j["poles"].size(), 2u);
  EXPECT_TRUE(j.contains("time_constants_s"));
  // A pole outside the unit circle: unstable, a negative (growth) time constant.
  RawLinearModel growing = Exact();
  growing.coefficients(0) = 1.2;
  growing.coefficients(1) = 0.0;
  const LocalDynamics g = AnalyseDynamics(Spec(), 0, growing, 0.0);
  EXPECT_FALSE(g.stable);
  EXPECT_LT(g.time_constants[0], 0.0);
  EXPECT_EQ(ToJson(g, 0).count("time_constants_samples"), 1u);
}

// The target: a one-rule model is ARX, so its local model's poles and gains are ARX's on the
// same regressor (to 1e-9), learned from the same data.
TEST(LocalDynamics, AOneRuleModelHasArxsPolesAndGains) {
  const Series data = Plant(600);
  const RegressorSpec spec = Spec();
  const ArxModel arx = ArxModel::Fit(spec, data);
  RawLinearModel arx_raw;
  arx_raw.constant = arx.coefficients()(0, 0);
  arx_raw.coefficients = arx.coefficients().col(0).tail(spec.size());
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = 0.0;  // one rule
  NarxModel model(spec, cfg);
  TrainOptions t;
  t.epochs = 1;
  t.refine_least_squares = true;  // the consequent by least squares, as ARX
  t.ridge = 0.0;                  // noiseless data: no ridge needed (ARX keeps its tiny one)
  Train(model, data, t);
  ASSERT_EQ(model.total_rules(), 1);
  const LocalDynamics mine = LocalModels(model, 0, 0.01).at(0);
  const LocalDynamics theirs = AnalyseDynamics(spec, 0, arx_raw, 0.01);
  ASSERT_EQ(mine.poles.size(), theirs.poles.size());
  for (std::size_t i = 0; i < mine.poles.size(); ++i) {
    EXPECT_NEAR(mine.poles[i].real(), theirs.poles[i].real(), 1e-9);
    EXPECT_NEAR(mine.poles[i].imag(), theirs.poles[i].imag(), 1e-9);
  }
  EXPECT_NEAR(mine.dc_gain[0].second, theirs.dc_gain[0].second, 1e-9);
  EXPECT_NEAR(mine.dc_gain[0].second, 3.5, 1e-6);  // and both the plant's
  // The rule's sentence carries them.
  const auto text = DescribeRules(model, 0, 0.01).at(0);
  EXPECT_NE(text.find("gain 3.5 from servo"), std::string::npos) << text;
  EXPECT_NE(text.find("τ 0.0561 s"), std::string::npos) << text;
}

}  // namespace
}  // namespace odonata::sysid

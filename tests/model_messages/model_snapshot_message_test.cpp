// Snapshots ⇄ models without a JSON detour: a model crosses the bus and comes back bit for bit
// (rules, consequents, learner state, pruning bookkeeping), and a snapshot that does not describe
// a valid model is refused naming what is wrong, as a model file would be.
#include "model_messages/model_snapshot_message.hpp"

#include <gtest/gtest.h>
#include <limits>

#include <cmath>
#include <functional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "../sysid/narendra_series.hpp"
#include "fuzzy/fuzzy_model_state.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/narx_model_state.hpp"

namespace odonata::model_messages {
namespace {

sysid::NarxModel Trained(fuzzy::ConsequentKind kind) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  cfg.entropy.threshold = 0.3;
  cfg.entropy.max_rules = 12;
  cfg.entropy.prune_utility = 0.01;  // pruning bookkeeping travels too
  cfg.forgetting = 0.999;
  sysid::NarxModel model(sysid::testing::NarendraSpec(), cfg);
  sysid::TrainOptions options;
  options.epochs = 2;
  options.fit_envelope = true;  // where its data end crosses with it (docs/identifier.md §7.3)
  Train(model, sysid::testing::NarendraTrain(800), options);
  return model;
}

void ExpectSameMessage(const odonata::model_snapshot_t& a, const odonata::model_snapshot_t& b) {
  // The encoded bytes hold every field, so equal bytes are equal messages.
  std::vector<uint8_t> ba(static_cast<std::size_t>(a.getEncodedSize()));
  std::vector<uint8_t> bb(static_cast<std::size_t>(b.getEncodedSize()));
  ASSERT_EQ(ba.size(), bb.size());
  a.encode(ba.data(), 0, static_cast<int>(ba.size()));
  b.encode(bb.data(), 0, static_cast<int>(bb.size()));
  EXPECT_EQ(ba, bb);
}

class SnapshotRoundTrip : public ::testing::TestWithParam<fuzzy::ConsequentKind> {};

TEST_P(SnapshotRoundTrip, AModelCrossesTheBusBitForBit) {
  const sysid::NarxModel model = Trained(GetParam());
  ASSERT_GT(model.total_rules(), 1);
  const odonata::model_snapshot_t msg = EncodeSnapshot(model);
  const sysid::NarxModel back = DecodeSnapshot(msg);
  EXPECT_EQ(back.ToJson(), model.ToJson());  // every field, as the model file writes it
  ExpectSameMessage(EncodeSnapshot(back), msg);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(model.spec().size(), -0.5, 0.7);
  EXPECT_EQ(back.Predict(x), model.Predict(x));  // bit for bit
  EXPECT_FALSE(back.limits().any());
  ASSERT_TRUE(back.envelope().any());
  const Eigen::VectorXd far = Eigen::VectorXd::Constant(model.spec().size(), 40.0);
  Eigen::VectorXd share;
  EXPECT_EQ(back.Predict(far, &share), model.Predict(far));  // the linear model out there
  EXPECT_EQ(share(0), 1.0);

  // A saturation limit (docs/identifier.md §7.2) crosses with the model.
  sysid::NarxModel held = model;
  sysid::OutputLimits limits;
  limits.lower = Eigen::VectorXd::Constant(1, -std::numeric_limits<double>::infinity());
  limits.upper = Eigen::VectorXd::Constant(1, 0.3);
  held.SetLimits(limits);
  const sysid::NarxModel held_back = DecodeSnapshot(EncodeSnapshot(held));
  ASSERT_TRUE(held_back.limits().any());
  EXPECT_EQ(held_back.ToJson(), held.ToJson());
  EXPECT_EQ(held_back.limits().upper(0), 0.3);
}

INSTANTIATE_TEST_SUITE_P(Consequents, SnapshotRoundTrip,
                         ::testing::Values(fuzzy::ConsequentKind::kSingleton,
                                           fuzzy::ConsequentKind::kLinear));

std::string DecodeError(const odonata::model_snapshot_t& msg) {
  try {
    DecodeSnapshot(msg);
  } catch (const std::runtime_error& e) {
    return e.what();
  }
  return "";
}

TEST(Snapshot, AnEnvelopeThatDoesNotFitTheModelIsRefused) {
  odonata::model_snapshot_t msg = EncodeSnapshot(Trained(fuzzy::ConsequentKind::kLinear));
  ASSERT_GT(msg.envelope_outputs, 0);
  msg.envelope_linear.pop_back();
  --msg.envelope_coefficients;
  EXPECT_NE(DecodeError(msg).find("envelope"), std::string::npos) << DecodeError(msg);
  msg = EncodeSnapshot(Trained(fuzzy::ConsequentKind::kLinear));
  msg.envelope_radius_widths[0] = -std::numeric_limits<double>::infinity();
  EXPECT_NE(DecodeError(msg).find("radius_widths"), std::string::npos) << DecodeError(msg);
}

TEST(Snapshot, AnInvalidModelIsRefusedNamingWhatIsWrong) {
  const odonata::model_snapshot_t good = EncodeSnapshot(Trained(fuzzy::ConsequentKind::kLinear));
  odonata::model_snapshot_t m = good;
  m.models[0].centres[0][0] = std::nan("");
  EXPECT_NE(DecodeError(m).find("centre is not finite"), std::string::npos) << DecodeError(m);
  m = good;
  m.models[0].sigmas[0][1] = -1.0;
  EXPECT_NE(DecodeError(m).find("is not in [sigma_min, 1e6]"), std::string::npos) << DecodeError(m);
  m = good;
  m.models[0].covariances[0][3] = INFINITY;
  EXPECT_NE(DecodeError(m).find("not finite"), std::string::npos) << DecodeError(m);
  m = good;
  m.models[0].num_rules += 1;  // counts that disagree with the arrays
  EXPECT_NE(DecodeError(m).find("disagree with num_rules"), std::string::npos) << DecodeError(m);
  m = good;
  m.models[0].entropy_threshold = 2.0;  // outside [0, kMaxRuleEntropy]: the core's own check
  EXPECT_NE(DecodeError(m).find("entropy threshold"), std::string::npos) << DecodeError(m);
  m = good;
  m.output_std[0] = 0.0;
  EXPECT_NE(DecodeError(m).find("standard deviation is not positive"), std::string::npos)
      << DecodeError(m);
  m = good;
  m.models[0].consequent = "quadratic";
  EXPECT_NE(DecodeError(m).find("quadratic"), std::string::npos) << DecodeError(m);
  m = good;
  m.output_upper[0] = std::nan("");
  EXPECT_NE(DecodeError(m).find("NaN limit"), std::string::npos) << DecodeError(m);
  m = good;
  m.output_lower[0] = 1.0;
  m.output_upper[0] = 0.0;
  EXPECT_NE(DecodeError(m).find("lower limit is not below"), std::string::npos) << DecodeError(m);
}

// Issue 51 point 1: finite but absurd values, each of which made a started identifier publish
// NaN from its fourth sample, are refused naming the field, as snapshots and as model files.
TEST(Snapshot, FiniteButAbsurdValuesAreRefusedNamingTheField) {
  const sysid::NarxModel trained = Trained(fuzzy::ConsequentKind::kLinear);
  const odonata::model_snapshot_t good = EncodeSnapshot(trained);
  const std::vector<std::pair<std::function<void(odonata::model_snapshot_t*)>, std::string>> cases{
      {[](auto* m) { m->models[0].covariances[0][0] = 1e300; }, "covariance entry beyond"},
      {[](auto* m) { m->models[0].rls_forgetting = 0.0; }, "forgetting"},
      {[](auto* m) { m->models[0].rls_initial_covariance = 1e300; }, "initial_covariance"},
      {[](auto* m) { m->models[0].coefficients[0][1] = 1e300; }, "coefficient beyond"},
      {[](auto* m) { m->models[0].sigmas[0][0] = 1e-300; }, "is not in [sigma_min, 1e6]"},
      {[](auto* m) { m->models[0].centres[0][0] = 1e300; }, "centre is not finite or beyond"},
      {[](auto* m) { m->models[0].output_widths[0] = 1e300; }, "output width"},
      {[](auto* m) { m->output_std[0] = 1e300; }, "beyond 1e200"},
      {[](auto* m) { m->regressor_half[0] = 1e-300; }, "below 1e-200"},
  };
  for (const auto& [spoil, want] : cases) {
    odonata::model_snapshot_t m = good;
    spoil(&m);
    EXPECT_NE(DecodeError(m).find(want), std::string::npos) << want << ": " << DecodeError(m);
  }
  EXPECT_EQ(DecodeError(good), "");
  // The same checks for a model file (one place for both, FromState).
  nlohmann::json file = trained.ToJson();
  file["models"][0]["consequent"]["forgetting"] = 0.0;
  EXPECT_THROW(sysid::NarxModel::FromJson(file), std::runtime_error);
  file = trained.ToJson();
  file["models"][0]["consequent"]["coefficients"][0][0] = 1e300;
  try {
    sysid::NarxModel::FromJson(file);
    ADD_FAILURE() << "a coefficient of 1e300 was read";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("coefficient beyond"), std::string::npos) << e.what();
  }
}

TEST(ModelState, TheFileAndTheStateAreTheSameModel) {
  for (const auto kind : {fuzzy::ConsequentKind::kSingleton, fuzzy::ConsequentKind::kLinear}) {
    const sysid::NarxModel model = Trained(kind);
    EXPECT_EQ(sysid::NarxModel::FromJson(model.ToJson()).ToJson(), model.ToJson());
    EXPECT_EQ(sysid::NarxModel::FromState(model.State()).ToJson(), model.ToJson());
    // The same check on both paths: a state the file reader would refuse is refused here too.
    sysid::NarxModelState bad = model.State();
    bad.models[0].rules[0].sigma[0] = 0.0;
    EXPECT_THROW(sysid::NarxModel::FromState(bad), std::runtime_error);
    nlohmann::json j = model.ToJson();
    j["models"][0]["rules"][0]["sigma"][0] = 0.0;
    EXPECT_THROW(sysid::NarxModel::FromJson(j), std::runtime_error);
  }
}

// An expert's names for its rules cross the bus with them, so a resumed or a watching process
// prints the rules as the expert wrote them; a snapshot whose names disagree with its rules is
// refused.
TEST(Snapshot, AnExpertsRuleNamesCrossTheBus) {
  sysid::NarxModelState state = Trained(fuzzy::ConsequentKind::kLinear).State();
  auto& rules = state.models[0].rules;
  ASSERT_GE(rules.size(), 2u);
  rules[0].names.terms.assign(rules[0].centre.size(), "");
  rules[0].names.terms[1] = "fast";
  rules[1].names.output = "hover";
  const sysid::NarxModel named = sysid::NarxModel::FromState(state);
  const odonata::model_snapshot_t msg = EncodeSnapshot(named);
  EXPECT_EQ(msg.models[0].num_named, msg.models[0].num_rules);
  const sysid::NarxModel back = DecodeSnapshot(msg);
  EXPECT_EQ(back.ToJson(), named.ToJson());
  EXPECT_EQ(back.model(0).names(0).terms[1], "fast");
  EXPECT_TRUE(back.model(0).names(1).terms.empty());
  EXPECT_EQ(back.model(0).names(1).output, "hover");
  odonata::model_snapshot_t bad = msg;
  bad.models[0].term_names[0].pop_back();
  bad.models[0].term_names[0].push_back(std::string(100, 'x'));
  EXPECT_NE(DecodeError(bad).find("names"), std::string::npos) << DecodeError(bad);
  // An unnamed model's snapshot carries none.
  EXPECT_EQ(EncodeSnapshot(Trained(fuzzy::ConsequentKind::kLinear)).models[0].num_named, 0);
}

}  // namespace
}  // namespace odonata::model_messages

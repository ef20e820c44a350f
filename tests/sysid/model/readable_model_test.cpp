// The readable form of a model (issue 49 point 1): shared named terms, lags as one clause, rules
// that read alike as one, a model whose local models coincide as "linear: one rule"; and it is a
// model: it predicts and is scored.
#include "sysid/model/readable_model.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "narendra_series.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/model/narx_model_state.hpp"

namespace odonata::sysid {
namespace {

NarxModel Trained(double threshold) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = threshold;
  NarxModel m(testing::NarendraSpec(), cfg);
  TrainOptions t;
  t.epochs = 2;
  Train(m, testing::NarendraTrain(2000), t);
  return m;
}

// Two rules whose local models are the same are one linear model, whatever the premises say
// (the Flapper's pitch loop printed as "thrust very low" / "thrust very high" with one THEN).
TEST(ReadableModel, RulesWithOneLocalModelReadAsOneLinearRuleAndPredictAlike) {
  NarxModelState state = Trained(0.45).State();
  auto& f = state.models[0];
  ASSERT_GE(f.rules.size(), 2u);
  for (auto& c : f.consequent.coefficients) c = f.consequent.coefficients[0];
  const NarxModel full = NarxModel::FromState(state);
  const ReadableModel r = MakeReadable(full, testing::NarendraTrain(2000));
  EXPECT_TRUE(r.linear[0]);
  EXPECT_EQ(r.model.model(0).rules(), 1);
  ASSERT_FALSE(r.sentences[0].empty());
  EXPECT_EQ(r.sentences[0][0].rfind("linear: one rule: ", 0), 0u) << r.sentences[0][0];
  const auto data = BuildRegression(full.spec(), testing::NarendraValidate(500));
  for (Eigen::Index t = 0; t < data.x.rows(); t += 7) {
    const Eigen::VectorXd x = data.x.row(t).transpose();
    EXPECT_NEAR(r.model.Predict(x)(0), full.Predict(x)(0), 1e-9);
  }
}

// A model with several regimes: at most five named terms per signal, no more rules than the full
// model, one clause per signal, and it predicts nearly as well.
TEST(ReadableModel, SharedTermsOneClausePerSignalAndAScore) {
  const NarxModel full = Trained(0.49);
  ASSERT_GT(full.total_rules(), 2);
  const ReadableModel r = MakeReadable(full, testing::NarendraTrain(2000));
  EXPECT_FALSE(r.linear[0]);
  EXPECT_LE(r.model.model(0).rules(), full.model(0).rules());
  std::set<std::string> terms;
  for (const auto& s : r.sentences[0]) {
    if (s.rfind("IF ", 0) != 0) continue;
    // "IF y is low AND u is high THEN …": one clause per signal, not one per lag.
    EXPECT_EQ(s.find("(k-1) is"), std::string::npos) << s;
    for (const char* name : {"very low", "low", "medium", "high", "very high"})
      if (s.find(std::string(" is ") + name + " ") != std::string::npos) terms.insert(name);
  }
  EXPECT_GE(terms.size(), 2u);
  EXPECT_LE(terms.size(), 5u);
  const Series validate = testing::NarendraValidate(800);
  const double full_ndei = full.Ndei(validate, false),
               readable_ndei = r.model.Ndei(validate, false);
  EXPECT_LT(readable_ndei, 2 * full_ndei + 0.05) << "full " << full_ndei;
}

// More readable rules than the cap: signals leave every premise, the cheapest first, until at
// most max_rules remain; the model still predicts, and every sentence is about the signals kept.
TEST(ReadableModel, AtMostMaxRulesASignalLeavingThePremisesFirst) {
  const NarxModel full = Trained(0.49);
  const Series train = testing::NarendraTrain(2000);
  ReadableOptions uncapped;
  uncapped.max_rules = 1000;
  const ReadableModel all = MakeReadable(full, train, 0, uncapped);
  ASSERT_GT(all.model.model(0).rules(), 2) << "the cap must have something to do";
  ReadableOptions capped;
  capped.max_rules = 2;
  const ReadableModel r = MakeReadable(full, train, 0, capped);
  EXPECT_LE(r.model.model(0).rules(), 2);
  EXPECT_GE(r.model.model(0).rules(), 1);
  // One signal is left: y or u, never both in one rule.
  for (const auto& s : r.sentences[0]) {
    if (s.rfind("IF ", 0) != 0) continue;
    EXPECT_EQ(s.find(" AND "), std::string::npos) << s;
  }
  const double ndei = r.model.Ndei(testing::NarendraValidate(800), false);
  EXPECT_TRUE(std::isfinite(ndei));
  // The default cap is seven.
  EXPECT_EQ(ReadableOptions{}.max_rules, 7);
  EXPECT_LE(MakeReadable(full, train).model.model(0).rules(), 7);
}

}  // namespace
}  // namespace odonata::sysid

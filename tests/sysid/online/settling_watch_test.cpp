// Has the model seen enough (issue 60 point 3; sysid/online/settling_watch): on an ARX plant the
// watch goes from short of excitation through still learning to settled, and an excitation that
// never visits a third of an input's range is short of excitation there, named.
#include "sysid/online/settling_watch.hpp"

#include <gtest/gtest.h>

#include <random>

#include "noisy_arx_plant.hpp"
#include "online_fixtures.hpp"
#include "sysid/estimation/narx_training.hpp"

namespace odonata::sysid {
namespace {

using testing::PitchFromServo;

Series Plant(unsigned seed, int samples, double lo, double hi) {
  return testing::NoisyFirstOrderPlant(seed, samples, lo, hi);
}

// One linear rule fitted by least squares on the whole range of u (the declared range).
NarxModel OneRule() {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  cfg.entropy.threshold = 0.0;
  NarxModel model(PitchFromServo(), cfg);
  TrainOptions t;
  t.epochs = 1;
  t.refine_least_squares = true;
  t.detect_output_limits = false;
  Train(model, Plant(1, 2000, -1.0, 1.0), t);
  return model;
}

// Observes every row of `data` as the identifier does: prediction before the sample is learned.
// The states of rule 1 after each sample.
std::vector<SettlingState> Watch(SettlingWatch& w, const NarxModel& m, const Series& data) {
  const RegressionData r = BuildRegression(m.spec(), data);
  std::vector<SettlingState> states;
  for (Eigen::Index k = 0; k < r.x.rows(); ++k) {
    const Eigen::VectorXd x = r.x.row(k).transpose();
    w.Observe(m, x, r.y.row(k).transpose(), m.Predict(x));
    states.push_back(w.Judge(m).at(0).rules.at(0).state);
  }
  return states;
}

TEST(SettlingWatch, GoesFromShortThroughLearningToSettledOnAWellExcitedPlant) {
  const NarxModel model = OneRule();
  SettlingWatch w;
  const auto states = Watch(w, model, Plant(2, 1500, -1.0, 1.0));
  EXPECT_EQ(states.front(), SettlingState::kShortOfExcitation);
  EXPECT_EQ(states.back(), SettlingState::kSettled) << w.Judge(model)[0].sentence;
  // The rule: never settled before the bound has held kSettledSamples, and never back once settled
  // here.
  const auto first_settled = std::find(states.begin(), states.end(), SettlingState::kSettled);

  ASSERT_NE(first_settled, states.end());
  EXPECT_GE(first_settled - states.begin(), SettlingWatch::kSettledSamples);
  EXPECT_NE(std::find(states.begin(), first_settled, SettlingState::kLearning), first_settled);
  const OutputSettling j = w.Judge(model)[0];
  EXPECT_EQ(j.state, SettlingState::kSettled);
  EXPECT_EQ(j.sentence, "settled");
  ASSERT_EQ(j.rules.size(), 1u);
  EXPECT_LT(j.rules[0].standard_error, SettlingWatch::kSettledStandardError);
  EXPECT_NEAR(j.rules[0].samples, 1499.0, 1e-6);
  ASSERT_EQ(j.regimes.size(), 6u);  // pitch(k) and servo(k), three thirds each
}

// A watch that has seen nothing of a model's rules (a model resumed frozen) says so: short of
// excitation, never "settled" for want of evidence against it; States says what Judge says, and
// follows it once the samples come.
TEST(SettlingWatch, WithoutEvidenceARuleIsShortNotSettled) {
  const NarxModel model = OneRule();
  const SettlingWatch none;
  EXPECT_EQ(none.States(model).at(0), SettlingState::kShortOfExcitation);
  const OutputSettling j = none.Judge(model).at(0);
  EXPECT_EQ(j.state, SettlingState::kShortOfExcitation);
  ASSERT_EQ(j.rules.size(), 1u);
  EXPECT_EQ(j.rules[0].samples, 0.0);
  EXPECT_NE(j.sentence.find("rule 1"), std::string::npos) << j.sentence;
  SettlingWatch w;
  Watch(w, model, Plant(2, 1500, -1.0, 1.0));
  EXPECT_EQ(w.States(model).at(0), w.Judge(model).at(0).state);
  EXPECT_EQ(w.States(model).at(0), SettlingState::kSettled);
}

TEST(SettlingWatch, ARegimeNeverVisitedIsNamedWithWhereToFly) {
  const NarxModel model = OneRule();
  SettlingWatch w;
  Watch(w, model, Plant(3, 1500, -1.0, -0.5));  // servo only in its low third
  const OutputSettling j = w.Judge(model)[0];
  EXPECT_EQ(j.state, SettlingState::kShortOfExcitation);
  // The two thirds never visited, side by side, are one place to fly, with its range.
  EXPECT_NE(j.sentence.find("servo(k) medium to high (-0.333 to 1): 0 samples"), std::string::npos)
      << j.sentence;
  EXPECT_EQ(j.sentence.find("servo(k) low"), std::string::npos) << j.sentence;
  EXPECT_NE(j.sentence.find("fly more there"), std::string::npos) << j.sentence;
  // The rule itself has what it needs: the regime, not the rule, is short.
  EXPECT_NE(j.rules.at(0).state, SettlingState::kShortOfExcitation);
}

TEST(SettlingWatch, AFewSamplesNameTheRuleAndItsCount) {
  const NarxModel model = OneRule();
  SettlingWatch w;
  const Series few = Plant(4, 4, -1.0, 1.0);
  Watch(w, model, few);
  const OutputSettling j = w.Judge(model)[0];
  EXPECT_EQ(j.state, SettlingState::kShortOfExcitation);
  EXPECT_NE(j.sentence.find("rule 1 ("), std::string::npos) << j.sentence;
  EXPECT_NE(j.sentence.find("): 3 samples"), std::string::npos) << j.sentence;
}

TEST(SettlingWatch, ANoisierPlantStaysLearningLonger) {
  // The bound is on the standard error: the same samples from a plant 10× noisier settle later.
  const NarxModel model = OneRule();
  SettlingWatch quiet, noisy;
  const Series data = Plant(5, 400, -1.0, 1.0);
  Series loud = data;
  std::mt19937 rng(9);
  std::normal_distribution<double> noise(0.0, 1.0);
  for (Eigen::Index t = 0; t < loud.outputs.rows(); ++t) loud.outputs(t, 0) += noise(rng);
  Watch(quiet, model, data);
  Watch(noisy, model, loud);
  EXPECT_GT(noisy.Judge(model)[0].rules[0].standard_error,
            3.0 * quiet.Judge(model)[0].rules[0].standard_error);
}

TEST(SettlingWatch, ARefitOnTooFewSamplesForARegressorStartsItsRulesFromNone) {
  // A landing whose archive holds no complete regressor (breaks everywhere) must not throw out of
  // the identifier's sample step: its rules are judged from the samples that come next.
  const NarxModel model = OneRule();
  SettlingWatch w;
  Watch(w, model, Plant(6, 300, -1.0, 1.0));
  Series kept = Plant(7, 1, -1.0, 1.0);
  EXPECT_NO_THROW(w.Rebuild(model, kept));
  EXPECT_EQ(w.Judge(model)[0].rules.at(0).samples, 0.0);
  EXPECT_EQ(w.Judge(model)[0].rules.at(0).state, SettlingState::kShortOfExcitation);
}

TEST(SettlingWatch, AModelOfAnotherShapeStartsItsJudgementAgain) {
  // Lags changed under it without a Clear: the regimes are those of the new regressor, never an
  // index of the old one read past the new one's end.
  const NarxModel one = OneRule();
  SettlingWatch w;
  Watch(w, one, Plant(8, 200, -1.0, 1.0));
  RegressorSpec wider = PitchFromServo();
  wider.output_lags = 3;
  wider.input_lags = 3;
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = fuzzy::ConsequentKind::kLinear;
  NarxModel other(wider, cfg);
  TrainOptions t;
  t.epochs = 1;
  t.detect_output_limits = false;
  const Series data = Plant(9, 300, -1.0, 1.0);
  Train(other, data, t);
  Watch(w, other, data);
  const OutputSettling j = w.Judge(other)[0];
  ASSERT_EQ(j.regimes.size(), 6u);
  EXPECT_EQ(j.regimes[0].signal, "servo(k)");
  int64_t visits = 0;
  for (const auto& g : j.regimes) visits += g.samples;
  EXPECT_EQ(visits, 2 * (300 - 3));  // the new model's samples only, each in one third per signal
}

TEST(SettlingWatch, TheIdentifierJudgesWhatItLearnsAndForgetsOnAReplacedModel) {
  using testing::Empty;
  using testing::Row;
  const Series train = testing::NarendraTrain(3000, 11);
  OnlineIdentifier id(Empty(fuzzy::ConsequentKind::kLinear, train));
  EXPECT_EQ(id.Settling().at(0).state, SettlingState::kShortOfExcitation);
  for (Eigen::Index k = 0; k < train.samples(); ++k) id.Push(Row(train, k));
  const OutputSettling seen = id.Settling().at(0);
  EXPECT_EQ(seen.rules.size(), static_cast<std::size_t>(id.model().model(0).rules()));
  double samples = 0.0;
  for (const auto& r : seen.rules) samples += r.samples;
  EXPECT_GT(samples, 2000.0);  // every learned sample fires its rules
  id.ReplaceModel(Empty(fuzzy::ConsequentKind::kLinear, train));
  EXPECT_EQ(id.Settling().at(0).sentence, "short of excitation: no rule yet");
}

}  // namespace
}  // namespace odonata::sysid

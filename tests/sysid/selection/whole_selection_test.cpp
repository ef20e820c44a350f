// Whole model selections, repeated: the scheduled refits' accuracy against the per-sample
// learner alone, steady-state refits reusing a selection, and a selection's independence of the
// thread count. Seconds in Release and minutes each under the sanitizers, so this executable is
// labelled slow (Release only). The refit machinery itself (worker thread, landings, replay) is
// tested under the sanitizers by online_identifier_test.cpp, and the selection by the fit tests.

#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "narendra_series.hpp"
#include "online_fixtures.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {
namespace {

using testing::Empty;
using testing::Row;

TEST(OnlineIdentifier, RefitsLearnFarBetterThanThePerSampleLearnerAlone) {
  const Series train = testing::NarendraTrain(1500);
  const Series validate = testing::NarendraValidate(500);
  RefitSchedule refit;
  refit.first = 250;
  refit.every = 500;
  refit.buffer = 1000;  // the last 1000 samples only
  refit.at_freeze = false;
  OnlineIdentifier plain(Empty(fuzzy::ConsequentKind::kLinear, train));
  OnlineIdentifier refitted(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) {
    plain.Push(Row(train, k));
    refitted.Push(Row(train, k));
  }
  refitted.Freeze();  // the refit in flight (begun at 1000) closes; no closing refit of its own
  refitted.Settle();
  const double with = refitted.model().Ndei(validate, true);
  EXPECT_EQ(refitted.refits(), 3);  // begun at 250, 500 and 1000
  const double without = plain.model().Ndei(validate, true);
  std::printf("validation free-run NDEI %.4f with refits, %.4f without\n", with, without);
  EXPECT_LT(with, 0.5 * without);
}

// At steady state, once a selection has seen a full buffer, a refit trains with the settings it
// chose instead of searching again (most of a refit's cost); the closing refit chooses. Counts
// decide, so odonata-fit's replay makes the same choices and lands the same model.
TEST(OnlineIdentifier, SteadyStateRefitsReuseTheLastSelection) {
  const Series train = testing::NarendraTrain(1000);
  RefitSchedule refit;
  refit.first = 100;
  refit.every = 200;  // begun at 100, 200, 400 (the buffer full), then 600 and 800
  refit.buffer = 400;
  OnlineIdentifier online(Empty(fuzzy::ConsequentKind::kLinear, train), refit);
  for (Eigen::Index k = 0; k < train.samples(); ++k) online.Push(Row(train, k));
  EXPECT_EQ(online.refits(), 4);      // 100, 200, 400 and 600 landed; 800 is in flight
  EXPECT_EQ(online.selections(), 3);  // 100, 200 and 400 searched; 600 reused 400's choice
  // and its model passed the checks 400's selection held its own to (SteadyStateHolds).
  EXPECT_EQ(online.steady_state_refused(), 0);
  EXPECT_EQ(online.incumbents_kept(), 0);
  online.Freeze();
  online.Settle();
  EXPECT_EQ(online.selections(), 4) << "the closing refit searches";
  const OnlineReplay replay =
      LearnOnline(Empty(fuzzy::ConsequentKind::kLinear, train), refit, train,
                  Empty(fuzzy::ConsequentKind::kLinear, train).scaling());
  EXPECT_EQ(replay.model.ToJson().dump(), online.model().ToJson().dump());
}

// The sweeps, the short list, the rest checks and the folds train on several threads; what they
// give must not depend on how many (issue 22: identical models for --threads 1 and 2).
TEST(ModelSelection, TheResultIsTheSameWhateverTheThreadCount) {
  SelectionOptions o;
  o.thresholds = {ThresholdForRadius(1.6), ThresholdForRadius(1.1), ThresholdForRadius(0.75)};
  o.kappas = {0.5, 1.0};
  o.max_epochs = 6;
  o.simulation = {{10, 4}, {40, 4}};
  const Series train = testing::NarendraTrain(800);
  std::vector<std::string> runs;
  for (unsigned threads : {1u, 2u, 5u}) {
    o.threads = threads;
    const SelectionResult r =
        SelectModel(testing::NarendraSpec(), fuzzy::FuzzyModelConfig{}, TrainOptions{}, train, o);
    std::ostringstream s;
    s.precision(17);
    for (const auto& c : r.candidates)
      s << ToString(c.consequent) << c.threshold << ' ' << c.kappa << ' ' << c.rules << ' '
        << c.epochs << ' ' << c.score << ' ' << c.rest_deviation << ' ' << c.deviation_ridge << ';';
    s << r.chosen << ' ' << r.linear_check.fuzzy_score << ' ' << r.linear_check.linear_score;
    runs.push_back(s.str());
  }
  EXPECT_EQ(runs[0], runs[1]);
  EXPECT_EQ(runs[0], runs[2]);
}

}  // namespace
}  // namespace odonata::sysid

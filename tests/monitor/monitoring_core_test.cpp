// The monitor's cores without transport: scores run by run with the events the operator is told
// of, and the services' heartbeats going silent and coming back.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <stdexcept>

#include "metrics/accuracy.hpp"
#include "monitoring/peer_table.hpp"
#include "monitoring/prediction_scoreboard.hpp"

namespace odonata::monitoring {
namespace {

Prediction At(int64_t k, double y, double yhat) {
  return {k, {"y"}, {y}, {yhat}, {yhat}, {3}, {}, {}, 0, {}, {}, {}};
}

// A prediction carrying the live ARX baseline (prediction_t.arx_*).
Prediction WithArx(int64_t k, double y, double yhat, double arx) {
  return {k, {"y"}, {y}, {yhat}, {yhat}, {3}, {arx}, {arx}, 0, {}, {}, {}};
}

// And K steps ahead: the model's ŷ(k | k−K) `ahead`, the live ARX's `arx_ahead`; one step ahead
// both are exact, so only the K-step scores can tell them apart.
Prediction WithAhead(int64_t k, double y, double ahead, double arx_ahead) {
  return {k, {"y"}, {y}, {y}, {y}, {3}, {y}, {y}, 50, {ahead}, {arx_ahead}, {}};
}

// Issue 60, the live side: the share of measurements within the identifier's interval and its
// mean width, one step and K steps ahead, counted only where the interval was known (not −1).
TEST(PredictionScoreboard, TalliesHowOftenTheMeasurementFellWithinTheInterval) {
  PredictionScoreboard board(ScoreboardOptions{});
  for (int64_t k = 0; k < 10; ++k) {
    Prediction p = WithAhead(k, 1.0, k % 2 == 0 ? 1.05 : 1.5, 1.0);
    p.interval_level = 0.9;
    p.half_width = {k < 2 ? -1.0 : 0.1};  // the first two: not known yet
    p.ahead_half_width = {0.1};           // ahead: 1.05 within ±0.1, 1.5 not
    board.Add(p);
  }
  const auto& o = board.output("y");
  EXPECT_EQ(o.one_step_interval.scored, 8);
  EXPECT_EQ(o.one_step_interval.covered, 8);  // one step ahead is exact (WithAhead)
  EXPECT_DOUBLE_EQ(o.one_step_interval.mean_width(), 0.2);
  EXPECT_EQ(o.ahead_interval.scored, 10);
  EXPECT_EQ(o.ahead_interval.covered, 5);
  EXPECT_EQ(o.free_run_interval.scored, 0) << "none carried";
  EXPECT_EQ(o.seen_enough, -1) << "none carried";
  const auto s = board.Summary()["outputs"]["y"]["interval"];
  EXPECT_EQ(s["level"], 0.9);
  EXPECT_DOUBLE_EQ(s["k_step"]["coverage"].get<double>(), 0.5);
  EXPECT_EQ(s["one_step"]["samples"], 8);
  // A NaN width is a bad prediction, refused whole.
  Prediction bad = WithAhead(10, 1.0, 1.0, 1.0);
  bad.half_width = {std::nan("")};
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
}

// The free-run interval and "seen enough" as the identifier sends them per sample: tallied and
// summarised; a state that is none of the three, or arrays of another size, refused whole.
TEST(PredictionScoreboard, TalliesTheFreeRunIntervalAndKeepsTheLatestSeenEnough) {
  PredictionScoreboard board(ScoreboardOptions{});
  for (int64_t k = 0; k < 10; ++k) {
    Prediction p{k, {"y"}, {1.0}, {1.0}, {k < 5 ? 1.1 : 2.0}, {3}, {}, {}, 0, {}, {}, {}};
    p.interval_level = 0.9;
    p.half_width = {0.1};
    p.free_run_half_width = {k == 0 ? -1.0 : 0.2};  // 1.1 within ±0.2 of 1, 2.0 not
    p.seen_enough = {k < 8 ? 1 : 2};
    board.Add(p);
  }
  const auto& o = board.output("y");
  EXPECT_EQ(o.free_run_interval.scored, 9);
  EXPECT_EQ(o.free_run_interval.covered, 4);
  EXPECT_EQ(o.seen_enough, 2);
  const auto s = board.Summary()["outputs"]["y"];
  EXPECT_EQ(s["interval"]["free_run"]["samples"], 9);
  EXPECT_EQ(s["seen_enough"], 2);
  Prediction bad{10, {"y"}, {1.0}, {1.0}, {1.0}, {3}, {}, {}, 0, {}, {}, {}};
  bad.seen_enough = {3};
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
  bad.seen_enough = {1, 1};
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
  bad.seen_enough = {};
  bad.free_run_half_width = {std::nan("")};
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
  EXPECT_EQ(board.last_sample(), 9) << "nothing of the refused ones counted";
}

// Over a full window the fuzzy model is scored against the live ARX on the same samples: the
// operator hears once when it stops beating linear and once when it beats it again.
TEST(PredictionScoreboard, SaysWhenTheFuzzyModelDoesNotBeatTheLiveArx) {
  ScoreboardOptions o;
  o.window_samples = 20;
  PredictionScoreboard board(o);
  const auto y = [](int64_t k) { return std::sin(0.3 * static_cast<double>(k)); };
  std::vector<ScoreEvent::Kind> heard;
  const auto add = [&](const Prediction& p) {
    for (const auto& e : board.Add(p))
      if (e.kind == ScoreEvent::Kind::kBehindArx || e.kind == ScoreEvent::Kind::kAheadOfArx)
        heard.push_back(e.kind);
  };
  // The fuzzy error 0.01, the ARX's 0.1: ahead, nothing said.
  for (int64_t k = 0; k < 40; ++k) add(WithArx(k, y(k), y(k) + 0.01, y(k) + 0.1));
  EXPECT_TRUE(heard.empty());
  EXPECT_FALSE(board.BehindArx("y"));
  // Then the other way round: once the window holds only those samples, it is behind.
  for (int64_t k = 40; k < 80; ++k) add(WithArx(k, y(k), y(k) + 0.1, y(k) + 0.01));
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_EQ(heard[0], ScoreEvent::Kind::kBehindArx);
  EXPECT_TRUE(board.BehindArx("y"));
  for (int64_t k = 80; k < 120; ++k) add(WithArx(k, y(k), y(k) + 0.01, y(k) + 0.1));
  ASSERT_EQ(heard.size(), 2u);
  EXPECT_EQ(heard[1], ScoreEvent::Kind::kAheadOfArx);
  const auto s = board.Summary()["outputs"]["y"];
  ASSERT_TRUE(s.contains("arx"));
  EXPECT_EQ(s["arx"]["one_step"]["samples"], 120);
  EXPECT_GT(s["window_one_step"]["fit"].get<double>(),
            s["arx"]["window_one_step"]["fit"].get<double>());
  EXPECT_FALSE(s["behind_arx"].get<bool>());
}

// Issue 47 point 5: with a horizon the comparison with linear is made K steps ahead, where a
// loop that integrates is judged, and the summary carries both K-step scores.
TEST(PredictionScoreboard, WithAHorizonTheModelIsComparedWithArxKStepsAhead) {
  ScoreboardOptions o;
  o.window_samples = 20;
  PredictionScoreboard board(o);
  const auto y = [](int64_t k) { return std::sin(0.3 * static_cast<double>(k)); };
  std::vector<ScoreEvent> heard;
  const auto add = [&](const Prediction& p) {
    for (const auto& e : board.Add(p))
      if (e.kind == ScoreEvent::Kind::kBehindArx || e.kind == ScoreEvent::Kind::kAheadOfArx)
        heard.push_back(e);
  };
  for (int64_t k = 0; k < 40; ++k) add(WithAhead(k, y(k), y(k) + 0.01, y(k) + 0.1));
  EXPECT_TRUE(heard.empty());
  // Equal one step ahead (both exact), behind K steps ahead: said, and said as 50-step.
  for (int64_t k = 40; k < 80; ++k) add(WithAhead(k, y(k), y(k) + 0.1, y(k) + 0.01));
  ASSERT_EQ(heard.size(), 1u);
  EXPECT_EQ(heard[0].kind, ScoreEvent::Kind::kBehindArx);
  EXPECT_EQ(heard[0].horizon, 50);
  EXPECT_TRUE(board.BehindArx("y"));
  const auto s = board.Summary()["outputs"]["y"];
  EXPECT_EQ(s["horizon"], 50);
  EXPECT_EQ(s["ahead"]["samples"], 80);
  EXPECT_EQ(s["arx"]["horizon"], 50);
  EXPECT_LT(s["window_ahead"]["fit"].get<double>(), s["arx"]["window_ahead"]["fit"].get<double>());
  // The K-step arrays must agree with the horizon: a horizon of 1 or a missing array is refused.
  Prediction bad = WithAhead(80, 0, 0, 0);
  bad.horizon = 1;
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
  bad.horizon = 50;
  bad.arx_ahead.clear();
  EXPECT_THROW(board.Add(bad), std::invalid_argument);
  EXPECT_EQ(board.last_sample(), 79);
}

TEST(PredictionScoreboard, PredictionsWithoutTheBaselineScoreAsBefore) {
  PredictionScoreboard board(ScoreboardOptions{});
  for (int64_t k = 0; k < 10; ++k) board.Add(At(k, 1.0 * k, 1.0 * k));
  EXPECT_FALSE(board.output("y").has_arx());
  EXPECT_FALSE(board.Summary()["outputs"]["y"].contains("arx"));
  // A baseline of the wrong length, or not finite, is a bad prediction: nothing changes.
  Prediction ragged = WithArx(10, 1.0, 1.0, 1.0);
  ragged.arx_free_run.clear();
  EXPECT_THROW(board.Add(ragged), std::invalid_argument);
  EXPECT_THROW(board.Add(WithArx(10, 1.0, 1.0, std::nan(""))), std::invalid_argument);
  EXPECT_EQ(board.last_sample(), 9);
}

TEST(PredictionScoreboard, ScoresTheRunAndStartsAfreshWhenTheSampleNumberGoesBack) {
  PredictionScoreboard board(ScoreboardOptions{});
  for (int64_t k = 0; k < 50; ++k) board.Add(At(k, std::sin(0.1 * k), std::sin(0.1 * k) + 0.01));
  EXPECT_EQ(board.last_sample(), 49);
  EXPECT_EQ(board.output("y").fuzzy.one_step.total.samples(), 50);
  board.Add(At(52, 0.0, 0.0));
  EXPECT_EQ(board.gaps(), 2);
  const auto events = board.Add(At(0, 0.5, 0.5));
  ASSERT_EQ(events.size(), 1u);
  EXPECT_EQ(events[0].kind, ScoreEvent::Kind::kNewRun);
  EXPECT_EQ(events[0].previous, 52);
  EXPECT_EQ(board.gaps(), 0);
  EXPECT_EQ(board.output("y").fuzzy.one_step.total.samples(), 1);
  const auto s = board.Summary();
  ASSERT_EQ(s["previous_runs"].size(), 1u);
  EXPECT_EQ(s["previous_runs"][0]["last_sample"], 52);
  EXPECT_EQ(s["outputs"]["y"]["rules"], 3);
}

TEST(PredictionScoreboard, ABadPredictionChangesNothing) {
  PredictionScoreboard board(ScoreboardOptions{});
  board.Add(At(0, 1.0, 1.0));
  EXPECT_THROW(board.Add(At(1, std::nan(""), 1.0)), std::invalid_argument);
  EXPECT_THROW(board.Add(At(0, 1.0, 1.0)), std::invalid_argument);              // a duplicate
  EXPECT_THROW(board.Add(At(1'000'000'000, 1.0, 1.0)), std::invalid_argument);  // a far leap
  Prediction ragged = At(1, 1.0, 1.0);
  ragged.free_run.clear();
  EXPECT_THROW(board.Add(ragged), std::invalid_argument);
  EXPECT_EQ(board.last_sample(), 0);
  EXPECT_NO_THROW(board.Add(At(1, 1.0, 1.0)));  // the genuine sample 1 still counts
  EXPECT_EQ(board.output("y").fuzzy.one_step.total.samples(), 2);
}

// Forged predictions with ever new output names cannot grow the board: at most kMaxOutputs per
// run, checked before anything changes (issue 24 point 5).
TEST(PredictionScoreboard, OutputsPerRunAreBounded) {
  PredictionScoreboard board(ScoreboardOptions{});
  const auto wide = [](int64_t k, std::size_t n, const std::string& prefix) {
    Prediction p;
    p.sample = k;
    for (std::size_t i = 0; i < n; ++i) {
      p.names.push_back(prefix + std::to_string(i));
      p.measured.push_back(1.0);
      p.predicted.push_back(1.0);
      p.free_run.push_back(1.0);
      p.rules.push_back(1);
    }
    return p;
  };
  EXPECT_THROW(board.Add(wide(0, 1000, "f")), std::invalid_argument);
  EXPECT_NO_THROW(board.Add(wide(0, 200, "a")));
  EXPECT_THROW(board.Add(wide(1, 100, "b")), std::invalid_argument);  // 300 in this run
  EXPECT_EQ(board.last_sample(), 0);
  EXPECT_NO_THROW(board.Add(wide(1, 200, "a")));  // the same names go on
  EXPECT_EQ(board.outputs().size(), 200u);
  EXPECT_NO_THROW(board.Add(wide(0, PredictionScoreboard::kMaxOutputs, "c")));  // a new run
  EXPECT_EQ(board.outputs().size(), PredictionScoreboard::kMaxOutputs);
}

TEST(PredictionScoreboard, WarnsOnceWhenTheWindowFitFallsAndOnceWhenItRecovers) {
  ScoreboardOptions o;
  o.window_samples = 20;
  o.warn_fit_percent = 80.0;
  PredictionScoreboard board(o);
  int low = 0, cleared = 0;
  const auto count = [&](const std::vector<ScoreEvent>& events) {
    for (const auto& e : events) {
      low += e.kind == ScoreEvent::Kind::kLowFit;
      cleared += e.kind == ScoreEvent::Kind::kLowFitCleared;
    }
  };
  int64_t k = 0;
  for (; k < 40; ++k) count(board.Add(At(k, std::sin(0.3 * k), std::sin(0.3 * k))));
  EXPECT_EQ(low, 0);
  for (; k < 80; ++k) count(board.Add(At(k, std::sin(0.3 * k), -std::sin(0.3 * k))));
  EXPECT_EQ(low, 1);
  EXPECT_TRUE(board.Warned("y"));
  for (; k < 120; ++k) count(board.Add(At(k, std::sin(0.3 * k), std::sin(0.3 * k))));
  EXPECT_EQ(cleared, 1);
  EXPECT_FALSE(board.Warned("y"));
}

TEST(PeerTable, SaysOnceWhenAServiceFallsSilentAndWhenItIsBack) {
  PeerTable peers;
  const auto t0 = PeerTable::Clock::time_point{};
  Heartbeat hb{"plant-1", "odonata-plant", "running"};
  EXPECT_TRUE(peers.OnHeartbeat(hb, t0).empty());
  EXPECT_TRUE(peers.CheckSilence(t0 + std::chrono::seconds(2), 3.0).empty());
  const auto silent = peers.CheckSilence(t0 + std::chrono::seconds(4), 3.0);
  ASSERT_EQ(silent.size(), 1u);
  EXPECT_EQ(silent[0].kind, PeerEvent::Kind::kSilent);
  EXPECT_TRUE(peers.CheckSilence(t0 + std::chrono::seconds(5), 3.0).empty());  // said once
  const auto back = peers.OnHeartbeat(hb, t0 + std::chrono::seconds(6));
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].kind, PeerEvent::Kind::kBack);
  hb.skipped = 3;
  const auto behind = peers.OnHeartbeat(hb, t0 + std::chrono::seconds(7));
  ASSERT_EQ(behind.size(), 1u);
  EXPECT_EQ(behind[0].kind, PeerEvent::Kind::kFallingBehind);
  EXPECT_EQ(peers.Summary()["plant-1"]["skipped"], 3);
  hb.state = "stopping";
  peers.OnHeartbeat(hb, t0 + std::chrono::seconds(8));
  EXPECT_TRUE(peers.CheckSilence(t0 + std::chrono::seconds(100), 3.0).empty());  // it said so
}

TEST(PeerTable, ForgetsTheLeastRecentlyHeardPastItsBound) {
  PeerTable peers;
  const auto t0 = PeerTable::Clock::time_point{};
  for (std::size_t i = 0; i < PeerTable::kMaxPeers + 10; ++i)
    peers.OnHeartbeat({"p" + std::to_string(i), "s", "running"}, t0 + std::chrono::seconds(i));
  EXPECT_EQ(peers.peers().size(), PeerTable::kMaxPeers);
  EXPECT_EQ(peers.peers().count("p0"), 0u);
  EXPECT_EQ(peers.peers().count("p265"), 1u);
}

TEST(PeerTable, TheSummaryKeepsWhatAServiceToldItsOperator) {
  // The identifier's "seen enough" (heartbeat_t::detail) goes into the monitor's summary, so a
  // run can be read after the flight; a service with nothing to tell adds no key.
  PeerTable peers;
  const auto t0 = PeerTable::Clock::time_point{};
  Heartbeat id{"id-1", "odonata-identifier", "running"};
  id.detail = "roll_rad: settled";
  peers.OnHeartbeat(id, t0);
  peers.OnHeartbeat({"plant-1", "odonata-plant", "running"}, t0);
  const nlohmann::json j = peers.Summary();
  EXPECT_EQ(j["id-1"]["detail"], "roll_rad: settled");
  EXPECT_FALSE(j["plant-1"].contains("detail"));
}

}  // namespace
}  // namespace odonata::monitoring

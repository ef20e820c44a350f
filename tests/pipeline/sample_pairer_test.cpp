// SamplePairer: which states, commands and beat states make sample k, message by message.
#include "pipeline/sample_pairer.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::pipeline {
namespace {

struct State {
  int64_t seq = 0;
  int64_t command_seq = -1;
};
struct Command {
  int64_t seq = 0;
  std::string source = "gen";
};
struct Beat {
  int64_t seq = 0;
  int64_t command_seq = -1;
};

using Pairer = SamplePairer<State, Command, Beat>;
using EventKind = Pairer::Event::Kind;

State S(int64_t k) { return {k, k - 1}; }
Command C(int64_t k, const std::string& source = "gen") { return {k, source}; }
Beat B(int64_t k) { return {k, k - 1}; }

// Collects what a series of calls produced.
struct Log {
  std::vector<Pairer::Event> events;
  void Add(std::vector<Pairer::Event> e) {
    for (auto& x : e) events.push_back(std::move(x));
  }
  std::vector<int64_t> Samples() const {
    std::vector<int64_t> k;
    for (const auto& e : events)
      if (e.kind == EventKind::kSample) k.push_back(e.index);
    return k;
  }
  int64_t Lost() const {
    int64_t n = 0;
    for (const auto& e : events)
      if (e.kind == EventKind::kGap) n += e.lost;
    return n;
  }
};

// The plant's order: state k, beat state k, then the generator's command k.
void Step(Pairer& p, Log& log, int64_t k, bool beats) {
  log.Add(p.OnState(S(k)));
  if (beats) log.Add(p.OnBeat(B(k)));
  log.Add(p.OnCommand(C(k)));
}

TEST(SamplePairer, SampleKIsStateKWithTheCommandStateKPlusOneAnswers) {
  Pairer p(PairingNeeds{});
  Log log;
  log.Add(p.OnState(S(0)));
  log.Add(p.OnCommand(C(0)));
  EXPECT_TRUE(log.events.empty());  // state 1 says which command was applied over [t_0, t_1)
  log.Add(p.OnState(S(1)));
  ASSERT_EQ(log.Samples(), (std::vector<int64_t>{0}));
  const auto& e = log.events.back();
  EXPECT_EQ(e.state.seq, 0);
  EXPECT_EQ(e.command.seq, 0);
  EXPECT_FALSE(e.beat);
  EXPECT_FALSE(e.next_beat);
}

TEST(SamplePairer, BeatAveragesFromBeatStateKAppliedCommandFromBeatStateKPlusOne) {
  Pairer p(PairingNeeds{true, true});
  Log log;
  for (int64_t k = 0; k < 5; ++k) Step(p, log, k, true);
  log.Add(p.OnState(S(5)));
  // Sample 4 is waiting for beat state 5, which the plant publishes right after state 5.
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2, 3}));
  log.Add(p.OnBeat(B(5)));
  ASSERT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2, 3, 4}));
  for (const auto& e : log.events) {
    ASSERT_TRUE(e.beat && e.next_beat);
    EXPECT_EQ(e.beat->seq, e.index);
    EXPECT_EQ(e.next_beat->seq, e.index + 1);
    EXPECT_EQ(e.next_beat->command_seq, e.command.seq);
  }
}

TEST(SamplePairer, ANeededMessageThatArrivesLateCompletesTheSample) {
  Pairer p(PairingNeeds{false, true});
  Log log;
  log.Add(p.OnState(S(0)));
  log.Add(p.OnCommand(C(0)));
  log.Add(p.OnState(S(1)));
  log.Add(p.OnState(S(2)));
  log.Add(p.OnCommand(C(1)));
  EXPECT_TRUE(log.Samples().empty());
  log.Add(p.OnBeat(B(1)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0}));
  log.Add(p.OnBeat(B(2)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(p.pending_states(), 0u);  // nothing waits but state 2, for state 3
}

TEST(SamplePairer, StatesWithoutACommandMakeNoSampleWhateverTheSignals) {
  // A real-time plant flies before the generator's first command: its states answer none.
  Pairer p(PairingNeeds{true, true});
  Log log;
  for (int64_t k = 0; k < 6; ++k) {
    log.Add(p.OnState(State{k, -1}));
    log.Add(p.OnBeat(Beat{k, -1}));
  }
  EXPECT_TRUE(log.Samples().empty());
  EXPECT_EQ(log.Lost(), 0);  // still waiting: nothing is lost before the limit
}

TEST(SamplePairer, AMissingBeatStateIsAGapNeverBridged) {
  Pairer p(PairingNeeds{true, true});
  Log log;
  const int64_t n = 20 + static_cast<int64_t>(Pairer::kMaxPendingStates);
  for (int64_t k = 0; k < n; ++k) {
    log.Add(p.OnState(S(k)));
    if (k != 10) log.Add(p.OnBeat(B(k)));
    log.Add(p.OnCommand(C(k)));
  }
  // Sample 9 lacks beat state 10's applied command, sample 10 its averages: both are lost, and
  // nothing else.
  const auto samples = log.Samples();
  EXPECT_EQ(log.Lost(), 2);
  EXPECT_EQ(std::count(samples.begin(), samples.end(), 9), 0);
  EXPECT_EQ(std::count(samples.begin(), samples.end(), 10), 0);
  EXPECT_EQ(samples.size(), static_cast<std::size_t>(n - 1 - 2));
  for (const auto& e : log.events) {
    if (e.kind == EventKind::kGap) {
      EXPECT_EQ(e.what, "missing beat state");
    }
  }
  // Until the limit, the pairer waits: a lost beat state stops the samples after it too.
  Pairer q(PairingNeeds{false, true});
  Log held;
  for (int64_t k = 0; k < 12; ++k) {
    held.Add(q.OnState(S(k)));
    if (k != 10) held.Add(q.OnBeat(B(k)));
    held.Add(q.OnCommand(C(k)));
  }
  EXPECT_EQ(held.Samples().back(), 8);
  EXPECT_EQ(held.Lost(), 0);
}

TEST(SamplePairer, FinishLosesWhatWaitsAndReleasesWhatFollows) {
  // The end of a recorded log: a missing beat state loses its samples at once, and the samples
  // after it, already complete, are released instead of waiting for the limit.
  Pairer p(PairingNeeds{false, true});
  Log log;
  for (int64_t k = 0; k < 12; ++k) {
    log.Add(p.OnState(S(k)));
    if (k != 10) log.Add(p.OnBeat(B(k)));
    log.Add(p.OnCommand(C(k)));
  }
  EXPECT_EQ(log.Samples().back(), 8);
  log.Add(p.Finish());
  EXPECT_EQ(log.Lost(), 1);  // sample 9: no beat state 10
  EXPECT_EQ(log.Samples().back(), 10);
  EXPECT_EQ(p.pending_states(), 0u);
  // Finish() changes nothing for later messages: the pairer waits again.
  log.Add(p.OnState(S(12)));
  EXPECT_EQ(log.Samples().back(), 10);  // sample 11 needs beat state 12
  log.Add(p.OnBeat(B(12)));
  EXPECT_EQ(log.Samples().back(), 11);
}

TEST(SamplePairer, ABeatStateAnsweringAnotherCommandIsNotPaired) {
  Pairer p(PairingNeeds{false, true});
  Log log;
  log.Add(p.OnState(S(0)));
  log.Add(p.OnBeat(B(0)));
  log.Add(p.OnCommand(C(0)));
  log.Add(p.OnState(S(1)));
  log.Add(p.OnBeat(Beat{1, 7}));  // not the command state 1 answers
  EXPECT_TRUE(log.Samples().empty());
}

TEST(SamplePairer, AGapInStatesIsReportedWithItsLength) {
  Pairer p(PairingNeeds{});
  Log log;
  const int64_t wait = static_cast<int64_t>(Pairer::kMaxStatesAfterHole);
  for (int64_t k = 0; k < 7 + wait - 1; ++k)
    if (k < 4 || k > 6) Step(p, log, k, false);
  // States 4, 5, 6 may still come: the states after them wait.
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2}));
  EXPECT_EQ(log.Lost(), 0);
  EXPECT_EQ(p.newest_held_state(), 3);
  Step(p, log, 7 + wait - 1, false);  // one too many waits: the hole is given up
  EXPECT_EQ(log.Lost(), 3);  // states 4, 5, 6 are missing: samples 3 … 6 cannot be formed
  const std::vector<int64_t> samples = log.Samples();
  EXPECT_EQ(samples.size(), 3u + static_cast<std::size_t>(wait - 1));
  EXPECT_EQ(samples[3], 7);
  EXPECT_EQ(samples.back(), 7 + wait - 2);
}

// A lockstep window: states overtake a lost one, whose resend comes later, out of order; beat
// states likewise. Every sample is formed, in order, none lost.
TEST(SamplePairer, AResentStateFillsItsHoleAndReleasesTheStatesAfterIt) {
  Pairer p(PairingNeeds{true, true});
  Log log;
  for (int64_t k = 0; k < 3; ++k) Step(p, log, k, true);
  log.Add(p.OnCommand(C(3)));
  log.Add(p.OnBeat(B(3)));  // state 3 lost; beat state 3 came
  for (int64_t k = 4; k < 6; ++k) log.Add(p.OnState(S(k)));
  log.Add(p.OnBeat(B(5)));  // beat state 4 lost
  log.Add(p.OnCommand(C(4)));
  log.Add(p.OnCommand(C(5)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1}));
  EXPECT_EQ(p.newest_held_state(), 2);
  log.Add(p.OnState(S(3)));                                   // the resend
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2}));  // sample 3 needs beat state 4
  EXPECT_EQ(p.newest_held_state(), 3);
  log.Add(p.OnState(S(3)));  // again: ignored
  log.Add(p.OnBeat(B(4)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2, 3, 4}));
  EXPECT_EQ(p.newest_held_state(), 5);
  EXPECT_EQ(log.Lost(), 0);
}

TEST(SamplePairer, ResendsAreIgnoredAndBadSeqsRejected) {
  Pairer p(PairingNeeds{true, true});
  Log log;
  for (int64_t k = 0; k < 3; ++k) Step(p, log, k, true);
  log.Add(p.OnState(S(2)));  // a lockstep resend of the latest state …
  log.Add(p.OnBeat(B(2)));   // … and its beat state
  log.Add(p.OnCommand(C(2)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1}));
  log.Add(p.OnState(S(1)));  // resends from further back (a lockstep window): ignored
  log.Add(p.OnBeat(B(1)));
  EXPECT_THROW(p.OnState(S(-3)), std::invalid_argument);
  EXPECT_THROW(p.OnBeat(B(-3)), std::invalid_argument);
  EXPECT_THROW(p.OnCommand(C(-3)), std::invalid_argument);
  EXPECT_THROW(p.OnState(S(int64_t{1} << 40)), std::invalid_argument);  // leaps too far
  EXPECT_THROW(p.OnBeat(B(int64_t{1} << 40)), std::invalid_argument);
  EXPECT_THROW(p.OnCommand(C(int64_t{1} << 40)), std::invalid_argument);
  EXPECT_THROW(p.OnCommand(C(2, "forger")), std::invalid_argument);  // the first command wins
  log.Add(p.OnState(S(3)));
  log.Add(p.OnBeat(B(3)));
  EXPECT_EQ(log.Samples(), (std::vector<int64_t>{0, 1, 2}));
  EXPECT_EQ(log.Lost(), 0);
  for (int64_t k = 4; k < 80; ++k) Step(p, log, k, true);
  EXPECT_THROW(p.OnState(S(5)), std::invalid_argument);  // beyond any resend: stale
  EXPECT_THROW(p.OnBeat(B(5)), std::invalid_argument);
}

// One forged in-window state, command and beat state far ahead (+900000) are held back, and the
// genuine run goes on: every sample formed, none lost.
TEST(SamplePairer, AForgedLeapCannotMakeTheGenuineRunStale) {
  Pairer p(PairingNeeds{true, true});
  Log log;
  for (int64_t k = 0; k < 5; ++k) Step(p, log, k, true);
  EXPECT_THROW(p.OnState(S(4 + 900000)), std::invalid_argument);
  EXPECT_THROW(p.OnBeat(B(4 + 900000)), std::invalid_argument);
  EXPECT_THROW(p.OnCommand(C(4 + 900000)), std::invalid_argument);
  for (int64_t k = 5; k < 20; ++k) Step(p, log, k, true);
  EXPECT_EQ(log.Samples().size(), 19u);  // samples 0 … 18 (19 waits for state 20)
  EXPECT_EQ(log.Lost(), 0);
  EXPECT_EQ(p.newest_held_state(), 19);
}

TEST(SamplePairer, APlantRestartForgetsTheOldRunWhicheverStreamRestartsFirst) {
  for (bool beat_first : {false, true}) {
    Pairer p(PairingNeeds{true, true});
    Log log;
    for (int64_t k = 0; k < 6; ++k) Step(p, log, k, true);
    if (beat_first) log.Add(p.OnBeat(B(0)));
    log.Add(p.OnState(S(0)));
    if (!beat_first) log.Add(p.OnBeat(B(0)));
    auto restarts = [&] {
      return std::count_if(log.events.begin(), log.events.end(),
                           [](const auto& e) { return e.kind == EventKind::kRestart; });
    };
    EXPECT_EQ(restarts(), 0) << "a fresh state 0 alone is only a candidate";
    const std::size_t before = log.Samples().size();
    log.Add(p.OnCommand(C(0)));  // the new run's command 0: kept aside until the plant answers
    log.Add(p.OnState(S(1)));    // its answer confirms the restart
    EXPECT_EQ(restarts(), 1);
    log.Add(p.OnBeat(B(1)));
    ASSERT_EQ(log.Samples().size(), before + 1) << "beat first: " << beat_first;
    EXPECT_EQ(log.events.back().index, 0);
    EXPECT_EQ(log.Lost(), 0);
  }
}

// One forged (or stale) fresh state 0 mid-run must not cut the run in two: the old run goes on,
// nothing is lost, and the commands that came meanwhile pair as they should.
TEST(SamplePairer, ALoneFreshStateZeroMidRunChangesNothing) {
  Pairer clean(PairingNeeds{true, true}), forged(PairingNeeds{true, true});
  Log a, b;
  for (int64_t k = 0; k < 40; ++k) {
    Step(clean, a, k, true);
    if (k == 20) {
      b.Add(forged.OnState(S(k)));
      b.Add(forged.OnBeat(B(k)));
      b.Add(forged.OnState(State{0, -1}));  // forged between state 20 and command 20
      b.Add(forged.OnCommand(C(k)));
    } else {
      Step(forged, b, k, true);
    }
  }
  EXPECT_EQ(b.Samples(), a.Samples());
  EXPECT_EQ(b.Lost(), 0);
  for (const auto& e : b.events) EXPECT_NE(e.kind, EventKind::kRestart);
  EXPECT_EQ(forged.newest_held_state(), clean.newest_held_state());
}

// A restarted plant left uncommanded repeats its state 0: the second one confirms the restart.
TEST(SamplePairer, ARepeatedFreshStateZeroConfirmsTheRestart) {
  Pairer p(PairingNeeds{false, false});
  Log log;
  for (int64_t k = 0; k < 10; ++k) Step(p, log, k, false);
  log.Add(p.OnState(State{0, -1}));
  log.Add(p.OnState(State{0, -1}));
  EXPECT_EQ(std::count_if(log.events.begin(), log.events.end(),
                          [](const auto& e) { return e.kind == EventKind::kRestart; }),
            1);
  const std::size_t before = log.Samples().size();
  log.Add(p.OnCommand(C(0)));
  log.Add(p.OnState(S(1)));
  ASSERT_EQ(log.Samples().size(), before + 1);
  EXPECT_EQ(log.events.back().index, 0);
}

}  // namespace
}  // namespace odonata::pipeline

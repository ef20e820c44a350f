// RunStart: the one rule for where a numbered stream's run begins again, with confirmation and
// far-below restarts as options (the generator's watch: both; DI-MAV states and the logger's
// receipts: confirmation only; signals_t: far below only).
#include "sequence/run_start.hpp"

#include <gtest/gtest.h>

namespace odonata::pipeline {
namespace {

using Kind = RunVerdict::Kind;
constexpr RunStartOptions kWatch = kRealtimeStates;
constexpr RunStartOptions kLockstepStates = kPairedStates;
constexpr RunStartOptions kSignals = kSignalSamples;

bool Restarts(RunStart& r, int64_t seq) { return r.Next(seq, seq == 0).kind == Kind::kRestart; }

TEST(RunStart, ARestartIsConfirmedByTheSeqAfterIt) {
  RunStart w(kWatch);
  for (int64_t s = 0; s <= 500; ++s) EXPECT_FALSE(Restarts(w, s));
  EXPECT_EQ(w.Next(0, true).kind, Kind::kCandidate);  // a candidate only
  const RunVerdict v = w.Next(1, false);
  EXPECT_EQ(v.kind, Kind::kRestart);
  EXPECT_TRUE(v.from_candidate);
  EXPECT_EQ(w.newest(), 1);
  for (int64_t s = 2; s <= 10; ++s) EXPECT_EQ(w.Next(s, false).kind, Kind::kNext);
}

TEST(RunStart, ALoneOldOrForgedSeqRestartsNothing) {
  RunStart w(kWatch, 500);
  EXPECT_FALSE(Restarts(w, 0));
  const RunVerdict next = w.Next(501, false);  // the old run goes on: the candidate is dropped
  EXPECT_EQ(next.kind, Kind::kNext);
  EXPECT_TRUE(next.dropped_candidate);
  EXPECT_FALSE(Restarts(w, 1));  // its successor comes too late to confirm it
  EXPECT_FALSE(Restarts(w, 502));
  // A late duplicate near the newest, then its successor (reordering): no restart either.
  EXPECT_EQ(w.Next(495, false).kind, Kind::kOlder);
  EXPECT_EQ(w.Next(496, false).kind, Kind::kOlder);
  EXPECT_EQ(w.newest(), 502);
}

TEST(RunStart, ARestartWhoseStartWasLostIsSeenFromTwoLowSeqsOnlyWhereAsked) {
  RunStart w(kWatch, 800);
  EXPECT_EQ(w.Next(3, false).kind, Kind::kCandidate);
  EXPECT_TRUE(Restarts(w, 4));
  // Lockstep states: a generator's resend reaches 64 back, so two low seqs are resends.
  RunStart states(kLockstepStates, 800);
  EXPECT_EQ(states.Next(740, false).kind, Kind::kOlder);
  EXPECT_EQ(states.Next(741, false).kind, Kind::kOlder);
  EXPECT_EQ(states.newest(), 800);
}

TEST(RunStart, AFarLeapAheadNeedsConfirmationBeforeItCounts) {
  RunStart w(kWatch, 100);
  const RunVerdict leap = w.Next(900000, false);  // forged or corrupt: held, not the newest
  EXPECT_EQ(leap.kind, Kind::kRefused);
  EXPECT_NE(leap.why.find("leaps"), std::string::npos) << leap.why;
  EXPECT_EQ(w.newest(), 100);
  EXPECT_FALSE(Restarts(w, 101));
  EXPECT_FALSE(Restarts(w, 102));  // a genuine successor: no false restart below a forged newest
  EXPECT_EQ(w.newest(), 102);
  EXPECT_EQ(w.Next(-3, false).kind, Kind::kRefused);
}

TEST(RunStart, WithoutConfirmationAStartRestartsAtOnce) {
  RunStart signals(kSignals);
  for (int64_t s = 0; s <= 50; ++s) EXPECT_EQ(signals.Next(s, s == 0).kind, Kind::kNext);
  const RunVerdict v = signals.Next(0, true);
  EXPECT_EQ(v.kind, Kind::kRestart);
  EXPECT_FALSE(v.from_candidate);
  EXPECT_EQ(signals.newest(), 0);
  // With it, the same start is held, and a second one (a restarted plant repeats its state 0
  // while nothing commands it) confirms it.
  RunStart states(kLockstepStates);
  for (int64_t s = 0; s <= 50; ++s) states.Next(s, s == 0);
  EXPECT_EQ(states.Next(0, true).kind, Kind::kCandidate);
  EXPECT_EQ(states.Next(0, true).kind, Kind::kRestart);
  EXPECT_EQ(states.newest(), 0);
}

TEST(RunStart, RightAfterARunsStartAStartRestartsAtOnceEvenWithConfirmation) {
  // A resent seq 1 of the old run could not tell the new run from it.
  RunStart states(kLockstepStates);
  states.Next(0, true);
  states.Next(1, false);
  EXPECT_EQ(states.Next(0, true).kind, Kind::kRestart);
  EXPECT_EQ(states.Next(0, true).kind, Kind::kOlder);  // the idle plant's repeat: a duplicate
  EXPECT_EQ(states.Next(1, false).kind, Kind::kNext);
}

TEST(RunStart, ARecorderKeepsALateIdleStateZeroAsACandidateOnly) {
  // State 0, the answer to command 0, then a late copy of the idle plant's state 0: the
  // identifier's pairing restarts at once (above), a recorder holds it until the run goes on.
  RunStart recorded(kRecordedStates);
  recorded.Next(0, true);
  recorded.Next(1, false);
  EXPECT_EQ(recorded.Next(0, true).kind, Kind::kCandidate);
  const RunVerdict next = recorded.Next(2, false);
  EXPECT_EQ(next.kind, Kind::kNext);
  EXPECT_TRUE(next.dropped_candidate);
}

TEST(RunStart, InRealTimeOnlyTheSuccessorConfirmsAStart) {
  // A real-time plant sends its state 0 once: a second copy is a duplicate, not a confirmation.
  RunStart w(kWatch, 500);
  EXPECT_EQ(w.Next(0, true).kind, Kind::kCandidate);
  EXPECT_NE(w.Next(0, true).kind, Kind::kRestart);
  EXPECT_EQ(w.Next(1, false).kind, Kind::kRestart);
  // Nor does a start right after the run's start restart it at once.
  RunStart fresh(kWatch, 0);
  fresh.Next(1, false);
  EXPECT_EQ(fresh.Next(0, true).kind, Kind::kCandidate);
  EXPECT_EQ(fresh.Next(2, false).kind, Kind::kNext);
}

}  // namespace
}  // namespace odonata::pipeline

// LockstepSequencer: the generator's side of the protocol, message by message.
#include "pipeline/lockstep_sequencer.hpp"

#include <stdexcept>

#include <gtest/gtest.h>

namespace odonata::pipeline {
namespace {

using Kind = SequencerAction::Kind;

TEST(LockstepSequencer, ResetThenOneCommandPerAnswer) {
  LockstepSequencer s(3, true, 2);
  EXPECT_EQ(s.Start().kind, Kind::kSendReset);
  EXPECT_EQ(s.OnState(5, 4, false).kind, Kind::kNone);  // the old run's state
  SequencerAction a = s.OnState(0, -1, false);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 0);
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);  // a late periodic state 0
  a = s.OnState(1, 0, false);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 1);
  EXPECT_EQ(s.OnState(1, 0, false).kind, Kind::kNone);  // duplicate answer
  EXPECT_EQ(s.OnState(2, 0, false).kind, Kind::kNone);  // wrong command_seq
  EXPECT_EQ(s.OnState(2, 1, false).seq, 2);
  EXPECT_EQ(s.OnState(3, 2, false).kind, Kind::kFinished);
  EXPECT_EQ(s.phase(), LockstepSequencer::Phase::kFinished);
  EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);
}

// A window of W commands in flight: the window slides over confirmed states, and an answer
// proves every earlier command applied (the plant applies them in seq order).
TEST(LockstepSequencer, AWindowKeepsWCommandsInFlight) {
  LockstepSequencer s(10, true, 2, 3, 4);
  EXPECT_EQ(s.window(), 4);
  s.Start();
  SequencerAction a = s.OnState(0, -1, false);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 0);
  EXPECT_EQ(a.count, 4);
  a = s.OnState(1, 0, false);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 4);
  EXPECT_EQ(a.count, 1);
  a = s.OnState(3, 2, false);  // the answer to command 1 was lost on the way here
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 5);
  EXPECT_EQ(a.count, 2);
  EXPECT_EQ(s.current(), 3);
  EXPECT_EQ(s.OnState(2, 1, false).kind, Kind::kNone);  // late: nothing new
  EXPECT_EQ(s.OnState(9, 8, false).kind, Kind::kNone);  // command 8 was never sent
  a = s.OnTimeout();                                    // everything in flight goes again
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_TRUE(a.resend);
  EXPECT_EQ(a.seq, 3);
  EXPECT_EQ(a.count, 4);
  EXPECT_EQ(s.OnState(7, 6, false).count, 3);  // 7, 8, 9
  EXPECT_EQ(s.sent(), 10);
  a = s.OnState(8, 7, false);  // the window slides, nothing is left to send
  EXPECT_EQ(a.kind, Kind::kNone);
  EXPECT_TRUE(a.progressed);
  EXPECT_FALSE(s.OnState(8, 7, false).progressed);
  EXPECT_EQ(s.OnState(10, 9, false).kind, Kind::kFinished);
  EXPECT_THROW(LockstepSequencer(10, true, 2, 3, 0), std::invalid_argument);
  EXPECT_THROW(LockstepSequencer(10, true, 2, 3, LockstepSequencer::kMaxWindow + 1),
               std::invalid_argument);
}

// With consumers the window slides only as far as the slowest receipt.
TEST(LockstepSequencer, AWindowSlidesOverAcknowledgedStatesOnly) {
  LockstepSequencer s(6, false, 3, 3, 3);
  s.AddConsumer("identifier");
  s.AddConsumer("logger");
  s.Start();
  s.OnState(0, -1, false);
  s.OnAck("identifier", 0);
  SequencerAction a = s.OnAck("logger", 0);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.count, 3);
  for (int64_t k = 1; k <= 3; ++k) EXPECT_EQ(s.OnState(k, k - 1, false).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("identifier", 3).kind, Kind::kNone);
  a = s.OnAck("logger", 2);  // the logger lost state 3
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 3);
  EXPECT_EQ(a.count, 2);
  a = s.OnTimeout();
  EXPECT_EQ(a.seq, 2);  // from command 2, whose answer the logger lacks
  EXPECT_EQ(a.count, 3);
  EXPECT_EQ(s.ack_resends(), 1);
  a = s.OnAck("logger", 3);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 5);
  EXPECT_EQ(a.count, 1);
}

// A consumer that restarted mid-run holds less than was confirmed: the resend reaches back to
// the answer it lacks (as far as the plant still answers), not only to the window.
TEST(LockstepSequencer, AResendReachesBackToWhatARestartedConsumerLacks) {
  LockstepSequencer s(200, false, 5, 3, 4);
  s.AddConsumer("a");
  s.AddConsumer("b");
  s.Start();
  s.OnState(0, -1, false);
  s.OnAck("a", 0);
  s.OnAck("b", 0);
  for (int64_t k = 1; k <= 100; ++k) {
    s.OnState(k, k - 1, false);
    s.OnAck("a", k);
    s.OnAck("b", k);
  }
  EXPECT_EQ(s.current(), 100);
  EXPECT_EQ(s.sent(), 104);
  s.OnAck("b", 95);  // restarted: it holds from a resent state 95 on, and lost 96
  SequencerAction a = s.OnTimeout();
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 95);  // state 96 answers command 95
  EXPECT_EQ(a.count, 104 - 95);
  s.OnAck("b", -1);  // restarted again, holding nothing: as far back as the plant answers
  a = s.OnTimeout();
  EXPECT_EQ(a.seq, 104 - LockstepSequencer::kResendReach);
}

// Once the plant has answered a command, a fresh state 0 is a restart even before the first
// answer is confirmed: a window may have been answered while the consumers catch up.
TEST(LockstepSequencer, ARestartBeforeTheFirstConfirmationIsSeen) {
  LockstepSequencer s(10, false, 5, 3, 4);
  s.AddConsumer("identifier");
  s.Start();
  s.OnState(0, -1, false);
  ASSERT_EQ(s.OnAck("identifier", 0).count, 4);
  s.OnState(1, 0, false);
  s.OnState(2, 1, false);
  EXPECT_EQ(s.current(), 0);  // the identifier has not acknowledged state 1 yet
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);  // suspected
  const SequencerAction a = s.OnState(0, -1, false);
  EXPECT_EQ(a.kind, Kind::kFailed);
  EXPECT_EQ(a.failure, SequencerAction::Failure::kRestarted);
}

// A hold stops the run with every state before it confirmed and nothing in flight; timeouts do
// not resend or fail meanwhile, and the release sends what the hold kept back.
TEST(LockstepSequencer, AHoldStandsStillUntilReleased) {
  LockstepSequencer s(10, true, 1, 3, 4);
  EXPECT_THROW(s.HoldAt(0), std::invalid_argument);
  EXPECT_THROW(s.HoldAt(10), std::invalid_argument);
  s.HoldAt(5);
  s.AddConsumer("ident");
  s.Start();
  s.OnState(0, -1, false);
  SequencerAction a = s.OnAck("ident", 0);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.count, 4);
  s.OnState(4, 3, false);
  a = s.OnAck("ident", 4);
  ASSERT_EQ(a.kind, Kind::kSendCommand);  // command 4 only: 5 is held back
  EXPECT_EQ(a.seq, 4);
  EXPECT_EQ(a.count, 1);
  EXPECT_FALSE(s.holding());
  s.OnState(5, 4, false);
  EXPECT_FALSE(s.holding());  // the consumer has not acknowledged state 5 yet
  a = s.OnAck("ident", 5);
  EXPECT_EQ(a.kind, Kind::kNone);
  EXPECT_TRUE(a.progressed);
  EXPECT_TRUE(s.holding());
  for (int i = 0; i < 5; ++i) EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);  // beyond max_resends
  EXPECT_EQ(s.phase(), LockstepSequencer::Phase::kAwaitingAnswer);
  a = s.ReleaseHold();
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 5);
  EXPECT_EQ(a.count, 4);
  EXPECT_FALSE(s.holding());
  EXPECT_EQ(s.OnTimeout().seq, 5);  // from here on timeouts resend again
}

// A receipt for a state that no command sent so far could have produced is forged: it must not
// slide the window for a consumer that holds nothing (issue: forged ODONATA_ACK).
TEST(LockstepSequencer, AReceiptForAStateNotYetPossibleIsIgnored) {
  LockstepSequencer s(100, true, 2, 3, 4);
  s.AddConsumer("ident");
  s.Start();
  s.OnState(0, -1, false);
  // Before command 0 a consumer may still acknowledge its previous run: it is there, and holds
  // state 0 of this one at most.
  SequencerAction a = s.OnAck("ident", 400);
  ASSERT_EQ(a.kind, Kind::kSendCommand);  // commands 0 … 3
  EXPECT_EQ(s.consumers().at("ident"), 0);
  EXPECT_EQ(s.OnAck("ident", 5000).kind, Kind::kNone);
  EXPECT_EQ(s.impossible_acks(), 1);
  EXPECT_EQ(s.consumers().at("ident"), 0);
  for (int64_t k = 1; k <= 4; ++k) EXPECT_EQ(s.OnState(k, k - 1, false).kind, Kind::kNone);
  EXPECT_EQ(s.current(), 0) << "the plant answered, but the consumer acknowledged nothing";
  a = s.OnAck("ident", 4);  // the genuine receipt
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(s.current(), 4);
}

TEST(LockstepSequencer, TimeoutsResendThenFail) {
  LockstepSequencer s(5, true, 2);
  s.Start();
  SequencerAction a = s.OnTimeout();
  EXPECT_EQ(a.kind, Kind::kSendReset);
  EXPECT_TRUE(a.resend);
  s.OnState(0, -1, false);
  s.OnState(1, 0, false);
  a = s.OnTimeout();
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 1);
  EXPECT_TRUE(a.resend);
  EXPECT_EQ(s.OnTimeout().seq, 1);
  a = s.OnTimeout();  // third consecutive timeout on command 1
  EXPECT_EQ(a.kind, Kind::kFailed);
  EXPECT_EQ(a.failure, SequencerAction::Failure::kNoAnswer);
  EXPECT_NE(a.message.find("command 1"), std::string::npos) << a.message;
  EXPECT_EQ(s.total_resends(), 3);
}

TEST(LockstepSequencer, ProgressClearsTheResendCount) {
  LockstepSequencer s(10, false, 1);
  EXPECT_EQ(s.Start().kind, Kind::kNone);  // no reset: just wait for state 0
  EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);
  s.OnState(0, -1, false);
  for (int64_t k = 0; k < 5; ++k) {
    EXPECT_EQ(s.OnTimeout().kind, Kind::kSendCommand);
    EXPECT_EQ(s.OnState(k + 1, k, false).kind, Kind::kSendCommand);
  }
}

TEST(LockstepSequencer, NoFreshPlantFails) {
  LockstepSequencer s(10, false, 1);
  s.Start();
  s.OnTimeout();
  const SequencerAction a = s.OnTimeout();
  EXPECT_EQ(a.kind, Kind::kFailed);
  EXPECT_NE(a.message.find("no fresh state 0"), std::string::npos) << a.message;
}

TEST(LockstepSequencer, DivergenceAndRestartFail) {
  LockstepSequencer s(10, true, 3);
  s.Start();
  s.OnState(0, -1, false);
  s.OnState(1, 0, false);
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);  // suspected: one could be forged
  EXPECT_EQ(s.OnState(0, -1, false).failure, SequencerAction::Failure::kRestarted);

  LockstepSequencer d(10, true, 3);
  d.Start();
  d.OnState(0, -1, false);
  EXPECT_EQ(d.OnState(1, 0, true).failure, SequencerAction::Failure::kDiverged);
  EXPECT_THROW(LockstepSequencer(0, true, 3), std::invalid_argument);
}

// Lossless: the next command waits for every consumer's receipt of the answer; a consumer that
// lost it is repaired by the resend of the command; one that never answers fails the run.
TEST(LockstepSequencer, TheNextCommandWaitsForEveryConsumer) {
  LockstepSequencer s(3, true, 2);
  s.AddConsumer("identifier");
  s.AddConsumer("logger");
  s.HoldStart();
  s.Start();
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);  // receipts of state 0 missing
  EXPECT_EQ(s.OnAck("identifier", 0).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("logger", 0).kind, Kind::kNone);  // the start is still held
  EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);         // discovering: nothing to resend or count
  SequencerAction a = s.ReleaseStart();
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 0);
  EXPECT_EQ(s.OnState(1, 0, false).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("logger", 1).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("stranger", 1).kind, Kind::kNone);  // not waited for: ignored
  a = s.OnTimeout();  // the identifier lost state 1 or command 0: both come again
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 0);
  EXPECT_EQ(s.ack_resends(), 1);
  a = s.OnAck("identifier", 1);
  ASSERT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 1);
  // Receipts before the plant's answer do not count the answer as received.
  EXPECT_EQ(s.OnAck("identifier", 2).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("logger", 2).kind, Kind::kNone);
  EXPECT_EQ(s.OnState(2, 1, false).seq, 2);
  // A consumer that stops cleanly is no longer waited for.
  EXPECT_EQ(s.OnState(3, 2, false).kind, Kind::kNone);
  EXPECT_EQ(s.OnAck("identifier", 3).kind, Kind::kNone);
  EXPECT_EQ(s.RemoveConsumer("logger").kind, Kind::kFinished);
}

TEST(LockstepSequencer, AConsumerThatNeverAcknowledgesFailsTheRun) {
  LockstepSequencer s(5, false, 2);
  s.AddConsumer("identifier");
  s.Start();
  s.OnState(0, -1, false);
  ASSERT_EQ(s.OnAck("identifier", 0).kind, Kind::kSendCommand);
  s.OnState(1, 0, false);
  EXPECT_EQ(s.OnTimeout().seq, 0);
  EXPECT_EQ(s.OnTimeout().seq, 0);
  const SequencerAction a = s.OnTimeout();
  EXPECT_EQ(a.kind, Kind::kFailed);
  EXPECT_EQ(a.failure, SequencerAction::Failure::kConsumerLost);
  EXPECT_NE(a.message.find("'identifier'"), std::string::npos) << a.message;
  EXPECT_NE(a.message.find("state 1"), std::string::npos) << a.message;
}

// A consumer landing a scheduled refit says so ("refitting"): its timeouts resend nothing and
// cost none of max_resends, and the run goes on when its receipts come; a consumer that is busy
// for ever still fails the run, and a busy flag for a stranger changes nothing.
TEST(LockstepSequencer, ABusyConsumerIsWaitedForWithoutResendsButNotForEver) {
  LockstepSequencer s(5, false, 1);
  s.AddConsumer("identifier");
  s.SetBusy("stranger", true);
  s.Start();
  s.OnState(0, -1, false);
  ASSERT_EQ(s.OnAck("identifier", 0).kind, Kind::kSendCommand);
  s.OnState(1, 0, false);
  s.SetBusy("identifier", true);
  for (int i = 0; i < 100; ++i) ASSERT_EQ(s.OnTimeout().kind, Kind::kNone) << i;
  EXPECT_EQ(s.busy_timeouts(), 100);
  EXPECT_EQ(s.total_resends(), 0);
  s.SetBusy("identifier", false);
  EXPECT_EQ(s.OnAck("identifier", 1).kind, Kind::kSendCommand);
  // Not busy: the usual patience (one resend, then the failure).
  s.OnState(2, 1, false);
  EXPECT_EQ(s.OnTimeout().kind, Kind::kSendCommand);
  EXPECT_EQ(s.OnTimeout().kind, Kind::kFailed);

  LockstepSequencer stuck(5, false, 1);
  stuck.AddConsumer("identifier");
  stuck.Start();
  stuck.OnState(0, -1, false);
  stuck.OnAck("identifier", 0);
  stuck.OnState(1, 0, false);
  stuck.SetBusy("identifier", true);
  for (int i = 0; i < LockstepSequencer::kMaxBusyTimeouts; ++i)
    ASSERT_EQ(stuck.OnTimeout().kind, Kind::kNone) << i;
  const SequencerAction a = stuck.OnTimeout();
  EXPECT_EQ(a.kind, Kind::kFailed);
  EXPECT_EQ(a.failure, SequencerAction::Failure::kConsumerLost);
  EXPECT_NE(a.message.find("busy"), std::string::npos) << a.message;
}

// A lone fresh state 0 mid-run (forged, or stale) does not abort the run: the plant's answer
// clears it, and without one the suspicion lapses after the confirmation timeouts, during which
// nothing is resent (a restarted plant would otherwise be commanded and its restart hidden).
TEST(LockstepSequencer, ALoneFreshStateZeroIsOnlyASuspicion) {
  LockstepSequencer s(10, true, 5, 3);
  s.Start();
  s.OnState(0, -1, false);
  s.OnState(1, 0, false);
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);
  EXPECT_EQ(s.OnState(2, 1, false).seq, 2);  // the genuine answer: the run goes on
  EXPECT_EQ(s.OnState(0, -1, false).kind, Kind::kNone);
  EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);  // no resend while suspected
  EXPECT_EQ(s.OnTimeout().kind, Kind::kNone);
  const SequencerAction a = s.OnTimeout();  // lapsed: resend as usual
  EXPECT_EQ(a.kind, Kind::kSendCommand);
  EXPECT_EQ(a.seq, 2);
  EXPECT_EQ(s.total_resends(), 1);
}

}  // namespace
}  // namespace odonata::pipeline

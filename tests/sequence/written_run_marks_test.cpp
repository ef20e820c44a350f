// ContiguousMark and WrittenRunMarks: what a consumer that keeps messages as they come (the
// logger) can acknowledge in a lockstep window.
#include "sequence/written_run_marks.hpp"

#include <gtest/gtest.h>

#include "sequence/contiguous_mark.hpp"

namespace odonata {
namespace {

TEST(ContiguousMark, StopsAtAHoleAndMovesOnWhenItsResendFillsIt) {
  ContiguousMark m;
  EXPECT_EQ(m.mark(), -1);
  m.Add(0);
  m.Add(1);
  m.Add(3);  // 2 lost
  m.Add(4);
  EXPECT_EQ(m.mark(), 1);
  m.Add(1);  // a resend of one counted already
  EXPECT_EQ(m.mark(), 1);
  m.Add(2);
  EXPECT_EQ(m.mark(), 4);
}

TEST(ContiguousMark, StartsWhereTheStreamIsUnlessToldWhereItStarts) {
  ContiguousMark joined;
  joined.Add(40);  // joined mid-run
  joined.Add(41);
  EXPECT_EQ(joined.mark(), 41);
  ContiguousMark fresh;
  fresh.ExpectFrom(0);
  EXPECT_EQ(fresh.mark(), -1);
  fresh.Add(1);  // 0 lost: its resend is still owed
  EXPECT_EQ(fresh.mark(), -1);
  fresh.Add(0);
  EXPECT_EQ(fresh.mark(), 1);
}

TEST(ContiguousMark, GivesUpAHoleOnceTooManySeqsWaitBehindIt) {
  ContiguousMark m(3);
  m.Add(0);
  for (int64_t k = 2; k <= 4; ++k) m.Add(k);
  EXPECT_EQ(m.mark(), 0);
  m.Add(5);  // a fourth behind the hole: 1 is given up
  EXPECT_EQ(m.mark(), 5);
  m.Add(1);  // too late: a resend as far as the mark knows
  EXPECT_EQ(m.mark(), 5);
}

// The plant's order: state k, beat state k, then the generator's command k.
void Step(WrittenRunMarks& m, int64_t k) {
  m.OnState(k, k == 0);
  m.OnBeat(k);
  m.OnCommand(k);
}

TEST(WrittenRunMarks, ALostCommandZeroHoldsTheReceiptsUntilItsResend) {
  WrittenRunMarks m;
  m.OnState(0, true);
  m.OnBeat(0);
  EXPECT_EQ(m.held(), 0);
  m.OnState(0, true);  // the uncommanded plant repeats its state 0: still held at once
  EXPECT_EQ(m.held(), 0);
  m.OnBeat(0);
  m.OnCommand(1);  // command 0 lost
  m.OnState(1, false);
  m.OnBeat(1);
  m.OnState(2, false);
  m.OnBeat(2);
  EXPECT_EQ(m.held(), 0);  // state 1 answers the command the log lacks
  m.OnCommand(0);          // the resend
  EXPECT_EQ(m.held(), 2);
}

TEST(WrittenRunMarks, EachStreamHoldsTheReceiptAtItsFirstHole) {
  WrittenRunMarks m;
  for (int64_t k = 0; k < 5; ++k) Step(m, k);
  EXPECT_EQ(m.held(), 4);
  m.OnState(6, false);  // state 5 lost
  m.OnBeat(5);
  m.OnBeat(6);
  m.OnCommand(5);
  EXPECT_EQ(m.held(), 4);
  m.OnState(5, false);
  EXPECT_EQ(m.held(), 6);
  m.OnState(7, false);
  m.OnCommand(6);
  EXPECT_EQ(m.held(), 6);  // beat state 7 missing
  m.OnBeat(7);
  EXPECT_EQ(m.held(), 7);
}

TEST(WrittenRunMarks, ALoggerThatJoinedMidRunStartsWhereTheRunIs) {
  WrittenRunMarks m;
  for (int64_t k = 40; k < 45; ++k) Step(m, k);
  EXPECT_EQ(m.held(), 44);
  // Then the plant is reset: its state 0 is a candidate, as for a logger that saw the run from
  // its start (the run rule has no exception for a late joiner) …
  m.OnState(0, true);
  m.OnBeat(0);
  EXPECT_EQ(m.held(), 44);
  m.OnCommand(0);
  m.OnState(1, false);  // … until the plant answers the new run's command 0
  m.OnBeat(1);
  EXPECT_EQ(m.held(), 1);
}

TEST(WrittenRunMarks, ALeapTooFarAheadMovesNoReceipt) {
  WrittenRunMarks m;
  for (int64_t k = 0; k < 5; ++k) Step(m, k);
  m.OnState(900000, false);  // forged or corrupt
  Step(m, 5);
  EXPECT_EQ(m.held(), 5);
}

TEST(WrittenRunMarks, ALoneFreshStateZeroMidRunMovesNothingBack) {
  WrittenRunMarks m;
  for (int64_t k = 0; k < 50; ++k) Step(m, k);
  m.OnState(0, true);  // stale or forged
  for (int64_t k = 50; k < 200; ++k) {
    Step(m, k);
    ASSERT_EQ(m.held(), k);
  }
  m.OnState(0, true);  // and once more, now that the first candidate has been dropped
  Step(m, 200);
  EXPECT_EQ(m.held(), 200);
}

TEST(WrittenRunMarks, ARestartedRunTakesOverOnceItsPlantAnswers) {
  WrittenRunMarks m;
  for (int64_t k = 0; k < 50; ++k) Step(m, k);
  m.OnState(0, true);  // the plant was reset …
  m.OnBeat(0);
  EXPECT_EQ(m.held(), 49);
  m.OnCommand(0);
  m.OnState(1, false);     // … and answered the new run's command 0
  EXPECT_EQ(m.held(), 0);  // beat state 1 still to come
  m.OnBeat(1);
  EXPECT_EQ(m.held(), 1);
  m.OnCommand(1);
  for (int64_t k = 2; k < 5; ++k) Step(m, k);
  EXPECT_EQ(m.held(), 4);
}

}  // namespace
}  // namespace odonata

// RestartWatch: a sender's numbering starting again is seen only when confirmed.
#include "sequence/restart_watch.hpp"

#include <gtest/gtest.h>

namespace odonata::pipeline {
namespace {

TEST(RestartWatch, ARestartIsConfirmedByTheSeqAfterIt) {
  RestartWatch w;
  for (int64_t s = 0; s <= 500; ++s) EXPECT_FALSE(w.Next(s));
  EXPECT_FALSE(w.Next(0));  // a candidate only
  EXPECT_TRUE(w.Next(1));
  EXPECT_EQ(w.newest(), 1);
  for (int64_t s = 2; s <= 10; ++s) EXPECT_FALSE(w.Next(s));
}

TEST(RestartWatch, ALoneOldOrForgedSeqRestartsNothing) {
  RestartWatch w(500);
  EXPECT_FALSE(w.Next(0));
  EXPECT_FALSE(w.Next(501));  // the old numbering goes on: the candidate is dropped
  EXPECT_FALSE(w.Next(1));    // its successor comes too late to confirm it
  EXPECT_FALSE(w.Next(502));
  // A late duplicate near the newest, then its successor (reordering): no restart either.
  EXPECT_FALSE(w.Next(495));
  EXPECT_FALSE(w.Next(496));
  EXPECT_EQ(w.newest(), 502);
}

TEST(RestartWatch, ARestartWhoseStateZeroWasLostIsSeenFromTwoLowSeqs) {
  RestartWatch w(800);
  EXPECT_FALSE(w.Next(3));
  EXPECT_TRUE(w.Next(4));
}

TEST(RestartWatch, AFarLeapAheadNeedsConfirmationBeforeItCounts) {
  RestartWatch w(100);
  EXPECT_FALSE(w.Next(900000));  // forged or corrupt: held, not the newest
  EXPECT_EQ(w.newest(), 100);
  EXPECT_FALSE(w.Next(101));
  EXPECT_FALSE(w.Next(102));  // a genuine successor: no false restart below a forged newest
  EXPECT_EQ(w.newest(), 102);
}

}  // namespace
}  // namespace odonata::pipeline

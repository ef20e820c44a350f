// ContiguousMark: what a consumer that keeps messages as they come can acknowledge.
#include "sequence/contiguous_mark.hpp"

#include <gtest/gtest.h>

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

TEST(ContiguousMark, StartsWhereTheStreamIsAndAfreshOnARestart) {
  ContiguousMark m;
  m.Add(40);  // joined mid-run
  m.Add(41);
  EXPECT_EQ(m.mark(), 41);
  m.Add(43);
  m.Add(0, true);
  EXPECT_EQ(m.mark(), 0);
  m.Add(1);
  EXPECT_EQ(m.mark(), 1);  // 43 belonged to the old run
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

}  // namespace
}  // namespace odonata

// RefitPatience: a lockstep sender waits without resending while only consumers landing a refit
// lack the awaited message, for at most its budget in a row (odonata-signal and odonata-replay).
#include "sequence/refit_patience.hpp"

#include <gtest/gtest.h>

namespace odonata::pipeline {
namespace {

using Verdict = RefitPatience::Verdict;

TEST(RefitPatience, OnlyRefittingLaggardsAreWaitedForWithoutResends) {
  RefitPatience p(3);
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kNotBusy) << "says nothing: a resend is due";
  p.SetBusy("id", true);  // heartbeat "refitting"
  EXPECT_EQ(p.OnTimeout({"id", "logger"}), Verdict::kNotBusy) << "the logger is not refitting";
  EXPECT_EQ(p.OnTimeout({}), Verdict::kNotBusy) << "nobody lacks it";
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kWait);
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kWait);
  EXPECT_EQ(p.in_a_row(), 2);
  p.Reset();  // the awaited message came
  EXPECT_EQ(p.in_a_row(), 0);
  EXPECT_EQ(p.total(), 2);
  p.SetBusy("id", false);  // landed
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kNotBusy);
}

TEST(RefitPatience, AStuckOrForgedRefittingIsGivenUpAfterTheBudget) {
  RefitPatience p(2);
  p.SetBusy("id", true);
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kWait);
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kWait);
  EXPECT_EQ(p.OnTimeout({"id"}), Verdict::kSpent);
  p.Forget("id");  // it left
  EXPECT_FALSE(p.busy("id"));
}

}  // namespace
}  // namespace odonata::pipeline

// RealtimePacer: each message of a paced run is due at its own time from the start, so a late
// send does not push the ones after it.
#include "pipeline/realtime_pacer.hpp"

#include <gtest/gtest.h>

namespace odonata::pipeline {
namespace {

using Clock = RealtimePacer::Clock;
using std::chrono::milliseconds;

TEST(RealtimePacer, EachSampleIsDueAtItsOwnTimeFromTheStart) {
  const Clock::time_point start{};
  const RealtimePacer pacer(start);
  EXPECT_EQ(pacer.DueAtSample(0, 100.0), start);
  EXPECT_EQ(pacer.DueAtSample(3, 100.0), start + milliseconds(30));  // 0.03 s, rounded, not cut
  EXPECT_EQ(pacer.DueAtSample(360000, 100.0), start + std::chrono::hours(1));  // no drift
}

TEST(RealtimePacer, ASpeedScalesTheRunsOwnTime) {
  const Clock::time_point start{};
  const RealtimePacer twice(start, 2.0);
  EXPECT_EQ(twice.DueAt(1.0), start + milliseconds(500));
}

TEST(RealtimePacer, ALateSampleGoesAtOnceAndTheNextKeepsItsTime) {
  const Clock::time_point start{};
  const RealtimePacer pacer(start);
  const Clock::time_point late = start + milliseconds(25);  // woke up 15 ms after sample 1
  EXPECT_EQ(RealtimePacer::Wait(pacer.DueAtSample(1, 100.0), late), Clock::duration::zero());
  EXPECT_EQ(RealtimePacer::Wait(pacer.DueAtSample(3, 100.0), late), milliseconds(5));
}

}  // namespace
}  // namespace odonata::pipeline

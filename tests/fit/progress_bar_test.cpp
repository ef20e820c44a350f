// The bar's time left: a phase's own pace, plus what the phases after it are expected to take.
#include "fit/progress_bar.hpp"

#include <gtest/gtest.h>

#include <limits>

namespace odonata::fit {
namespace {

TEST(ProgressBar, TimeLeftIsThePhasesPaceAndTheTimeAfterIt) {
  // A quarter done in 5 s: 15 s left of the phase.
  EXPECT_EQ(ProgressBar::TimeLeft(5.0, 0.25), "~15 s left");
  // The final training expected to take 20 s after it.
  EXPECT_EQ(ProgressBar::TimeLeft(5.0, 0.25, 20.0), "~35 s left");
  EXPECT_EQ(ProgressBar::TimeLeft(5.0, 0.25, 100.0), "~2 min left");
  // An estimate that is no number adds nothing; nor before the pace is known.
  EXPECT_EQ(ProgressBar::TimeLeft(5.0, 0.25, std::numeric_limits<double>::quiet_NaN()),
            "~15 s left");
  EXPECT_EQ(ProgressBar::TimeLeft(0.2, 0.25, 20.0), "");
  EXPECT_EQ(ProgressBar::TimeLeft(5.0, 0.01, 20.0), "");
}

}  // namespace
}  // namespace odonata::fit

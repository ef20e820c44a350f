#include "signals/aprbs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace odonata::signals {
namespace {

// Lengths of the runs of equal consecutive values.
std::vector<int> RunLengths(const std::vector<double>& v) {
  std::vector<int> runs;
  for (std::size_t k = 0; k < v.size(); ++k) {
    if (k == 0 || v[k] != v[k - 1]) runs.push_back(0);
    ++runs.back();
  }
  return runs;
}

TEST(Aprbs, LevelsStayInRangeAndHoldTheirLength) {
  const AprbsOptions o{2.0, 5.0, 30, 200};
  const std::vector<double> v = AprbsSequence(20000, o, 7);
  ASSERT_EQ(v.size(), 20000u);
  double lo = 1e9, hi = -1e9;
  for (const double x : v) {
    lo = std::min(lo, x);
    hi = std::max(hi, x);
  }
  EXPECT_GE(lo, 2.0);
  EXPECT_LT(hi, 5.0);
  // Over ~175 levels the range is covered, not just a corner of it.
  EXPECT_LT(lo, 2.2);
  EXPECT_GT(hi, 4.8);
  const std::vector<int> runs = RunLengths(v);
  // Every run but the cut-off last one lies within the hold bounds.
  for (std::size_t i = 0; i + 1 < runs.size(); ++i) {
    EXPECT_GE(runs[i], 30) << i;
    EXPECT_LE(runs[i], 200) << i;
  }
}

TEST(Aprbs, FixedHoldsAlignLevelsToBlocks) {
  const std::vector<double> v = AprbsSequence(250, {0.0, 1.0, 25, 25}, 3);
  for (std::size_t k = 0; k < v.size(); ++k) EXPECT_EQ(v[k], v[k - k % 25]) << k;
  EXPECT_NE(v[0], v[25]);
}

TEST(Aprbs, SameSeedSameSequenceOtherSeedOther) {
  const AprbsOptions o{-1.0, 1.0, 10, 50, 5};
  EXPECT_EQ(AprbsSequence(3000, o, 11), AprbsSequence(3000, o, 11));
  EXPECT_NE(AprbsSequence(3000, o, 11), AprbsSequence(3000, o, 12));
  // A shorter request is a prefix of a longer one.
  const std::vector<double> long_run = AprbsSequence(3000, o, 11);
  const std::vector<double> short_run = AprbsSequence(1000, o, 11);
  EXPECT_TRUE(std::equal(short_run.begin(), short_run.end(), long_run.begin()));
}

TEST(Aprbs, SmoothingIsATrailingMeanThatBoundsEachStep) {
  const AprbsOptions raw{-1.0, 1.0, 20, 40, 1};
  AprbsOptions smooth = raw;
  smooth.smooth = 10;
  const std::vector<double> r = AprbsSequence(2000, raw, 5);
  const std::vector<double> s = AprbsSequence(2000, smooth, 5);
  for (std::size_t k = 9; k < r.size(); ++k) {
    double sum = 0.0;
    for (std::size_t i = k - 9; i <= k; ++i) sum += r[i];
    EXPECT_NEAR(s[k], sum / 10.0, 1e-12);
    // A step of at most 2 spread over 10 samples.
    if (k > 0) {
      EXPECT_LE(std::abs(s[k] - s[k - 1]), 0.2 + 1e-12);
    }
  }
}

TEST(Aprbs, RejectsImpossibleOptions) {
  EXPECT_THROW(AprbsSequence(10, {1.0, 0.0, 1, 1}, 1), std::invalid_argument);
  EXPECT_THROW(AprbsSequence(10, {0.0, 1.0, 0, 5}, 1), std::invalid_argument);
  EXPECT_THROW(AprbsSequence(10, {0.0, 1.0, 6, 5}, 1), std::invalid_argument);
  EXPECT_NE(AprbsProblems({0.0, 1.0, 0, 0}), "");
  EXPECT_EQ(AprbsProblems({0.0, 1.0, 1, 1}), "");
}

}  // namespace
}  // namespace odonata::signals

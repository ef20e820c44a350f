// RowDecimator: blocks aligned to the sample index, inputs averaged in sample order, the rest at
// the block's first sample, and a block with a missing sample dropped whole.
#include "io/row_decimator.hpp"

#include <gtest/gtest.h>

#include <vector>

namespace odonata::io {
namespace {

TEST(RowDecimator, AveragesInputsAndKeepsTheRestAtTheBlocksFirstSample) {
  RowDecimator d(3, {false, true});  // [output, input]
  std::vector<std::vector<double>> rows;
  for (int64_t k = 0; k < 9; ++k) {
    if (auto r = d.Push(k, {10.0 * k, static_cast<double>(k)})) rows.push_back(*r);
  }
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[0], (std::vector<double>{0.0, 1.0}));   // y(0), mean u(0..2)
  EXPECT_EQ(rows[1], (std::vector<double>{30.0, 4.0}));  // y(3), mean u(3..5)
  EXPECT_EQ(rows[2], (std::vector<double>{60.0, 7.0}));  // y(6), mean u(6..8)
  EXPECT_EQ(d.dropped_blocks(), 0);
}

TEST(RowDecimator, SumsInSampleOrderThenDivides) {
  // The order of the floating-point operations is part of the contract: odonata-sim, the log
  // export and the identifier must agree bit for bit.
  RowDecimator d(3, {true});
  const double a = 0.1, b = 0.2, c = 0.3;
  d.Push(0, {a});
  d.Push(1, {b});
  const auto r = d.Push(2, {c});
  ASSERT_TRUE(r);
  EXPECT_EQ((*r)[0], ((a + b) + c) / 3);
}

TEST(RowDecimator, AlignsToTheIndexAndDropsABlockWithAMissingSample) {
  RowDecimator d(4, {true});
  std::vector<int64_t> completed;
  for (int64_t k : {2, 3, 4, 5, 6, 7, 8, 9, 11, 12, 13, 14, 15, 16}) {
    if (d.Push(k, {1.0})) completed.push_back(k);
  }
  // 2, 3: before the first boundary; 4–7 complete; 8–11 lacks 10; 12–15 complete.
  EXPECT_EQ(completed, (std::vector<int64_t>{7, 15}));
  EXPECT_EQ(d.dropped_blocks(), 1);
  EXPECT_FALSE(d.Push(15, {1.0})) << "a repeated index is ignored";
}

TEST(RowDecimator, FactorOnePassesEveryRowUnchanged) {
  RowDecimator d(1, {true, false});
  const auto r = d.Push(5, {0.25, 3.0});
  ASSERT_TRUE(r);
  EXPECT_EQ(*r, (std::vector<double>{0.25, 3.0}));
}

TEST(RowDecimator, ResetStartsAfresh) {
  RowDecimator d(2, {true});
  d.Push(10, {1.0});
  d.Reset();
  EXPECT_FALSE(d.Push(0, {2.0}));
  const auto r = d.Push(1, {4.0});
  ASSERT_TRUE(r);
  EXPECT_EQ((*r)[0], 3.0);
}

}  // namespace
}  // namespace odonata::io

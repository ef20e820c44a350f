#pragma once
// Identification at a lower rate than the plant's (docs/identifier.md §7): one row per block of
// samples. One class for odonata-sim's CSV, odonata-logger's export and the online identifier,
// so the three decimate alike, bit for bit.

#include <cstdint>
#include <optional>
#include <vector>

namespace odonata::io {

/// Block j holds samples j·N … j·N + N − 1 (aligned to the sample index, so every consumer of
/// the same run cuts the same blocks). Its row: columns marked as inputs averaged over the block
/// (summed in sample order, then divided by N); every other column as at the block's first
/// sample. An input over [t_k, t_k+1) so becomes the mean command over the block, and an output
/// the measurement at its start: row j + 1's output answers row j's input, as at full rate.
/// A block with a missing sample is dropped whole: it would average a different span.
class RowDecimator {
 public:
  /// @pre factor ≥ 1.
  RowDecimator(int factor, std::vector<bool> is_input);
  /// Feeds sample `index` (increasing; a repeated or older index is ignored). Returns the
  /// block's row when this sample completes one.
  /// @pre row.size() == is_input.size().
  std::optional<std::vector<double>> Push(int64_t index, const std::vector<double>& row);
  /// Blocks given up because a sample was missing.
  int64_t dropped_blocks() const { return dropped_; }
  int factor() const { return factor_; }
  /// Starts afresh (a new run).
  void Reset();

 private:
  int factor_;
  std::vector<bool> is_input_;
  std::vector<double> block_;
  int64_t next_index_ = -1;  // the sample the open block expects next; -1: none open
  int in_block_ = 0;
  int64_t dropped_ = 0;
  int64_t last_index_ = -1;
};

}  // namespace odonata::io

#include "io/row_decimator.hpp"

#include "contract/precondition.hpp"

namespace odonata::io {

RowDecimator::RowDecimator(int factor, std::vector<bool> is_input)
    : factor_(factor), is_input_(std::move(is_input)), block_(is_input_.size()) {
  ODONATA_EXPECTS(factor >= 1);
}

void RowDecimator::Reset() {
  next_index_ = -1;
  in_block_ = 0;
  last_index_ = -1;
}

std::optional<std::vector<double>> RowDecimator::Push(int64_t index,
                                                      const std::vector<double>& row) {
  ODONATA_EXPECTS(row.size() == is_input_.size());
  if (index <= last_index_) return std::nullopt;
  last_index_ = index;
  if (in_block_ > 0 && index != next_index_) {
    ++dropped_;  // a sample of the open block is missing
    in_block_ = 0;
  }
  if (in_block_ == 0) {
    if (index % factor_ != 0) return std::nullopt;  // wait for the next block's first sample
    block_ = row;
  } else {
    for (std::size_t i = 0; i < row.size(); ++i) {
      if (is_input_[i]) block_[i] += row[i];
    }
  }
  next_index_ = index + 1;
  if (++in_block_ < factor_) return std::nullopt;
  in_block_ = 0;
  if (factor_ > 1) {
    for (std::size_t i = 0; i < block_.size(); ++i) {
      if (is_input_[i]) block_[i] /= factor_;
    }
  }
  return block_;
}

}  // namespace odonata::io

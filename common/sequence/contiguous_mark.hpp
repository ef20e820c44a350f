#pragma once
// The newest seq of a stream up to which nothing is missing, when messages may overtake a lost
// one and its resend comes later (a lockstep window, docs/lcm.md §10): what a consumer that keeps
// messages as they come (odonata-logger) can acknowledge. Seqs after a hole are remembered until
// the hole fills; with more than `max_after_hole` of them the hole is given up, so a stream that
// is never repaired (real time) keeps moving.

#include <cstddef>
#include <cstdint>
#include <set>

namespace odonata {

class ContiguousMark {
 public:
  explicit ContiguousMark(std::size_t max_after_hole = 64) : max_after_hole_(max_after_hole) {}

  /// Seq `seq` arrived. The first seq starts the mark wherever it is (a consumer that joins
  /// mid-run); `restart` (the sender began a new run) starts it afresh at `seq`.
  void Add(int64_t seq, bool restart = false) {
    if (restart || mark_ < 0) {
      mark_ = seq;
      after_hole_.clear();
    } else if (seq > mark_ + 1) {
      after_hole_.insert(seq);
      if (after_hole_.size() > max_after_hole_) mark_ = *after_hole_.begin();
    } else if (seq == mark_ + 1) {
      mark_ = seq;
    }
    // Older seqs are resends: already counted.
    while (!after_hole_.empty() && *after_hole_.begin() <= mark_ + 1) {
      if (*after_hole_.begin() == mark_ + 1) ++mark_;
      after_hole_.erase(after_hole_.begin());
    }
  }

  /// -1 before any seq.
  int64_t mark() const { return mark_; }

 private:
  std::size_t max_after_hole_;
  int64_t mark_ = -1;
  std::set<int64_t> after_hole_;
};

}  // namespace odonata

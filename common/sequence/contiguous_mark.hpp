#pragma once
// The newest seq of a stream up to which nothing is missing, when messages may overtake a lost
// one and its resend comes later (a lockstep window, docs/lcm.md §10). Seqs after a hole are
// remembered until the hole fills; with more than `max_after_hole` of them the hole is given up,
// so a stream that is never repaired (real time) keeps moving.

#include <cstddef>
#include <cstdint>
#include <set>

namespace odonata {

class ContiguousMark {
 public:
  explicit ContiguousMark(std::size_t max_after_hole = 64) : max_after_hole_(max_after_hole) {}

  /// The stream (re)starts: `next` is the first seq it will count. Without a call, the first seq
  /// that arrives starts the mark (a receiver that joins mid-run).
  void ExpectFrom(int64_t next) {
    mark_ = next - 1;
    started_ = true;
    after_hole_.clear();
  }

  /// Seq `seq` arrived.
  void Add(int64_t seq) {
    if (!started_) {
      ExpectFrom(seq);
    }
    if (seq > mark_ + 1) {
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

  /// The newest seq with none missing before it since the start; start - 1 before any.
  int64_t mark() const { return started_ ? mark_ : -1; }

 private:
  std::size_t max_after_hole_;
  bool started_ = false;
  int64_t mark_ = -1;
  std::set<int64_t> after_hole_;
};

}  // namespace odonata

#pragma once
// Sees a sender number its messages from 0 again mid-stream — a real-time plant killed and
// started anew, which nobody reset — from the seqs alone. One seq proves nothing (a stale,
// duplicated or forged packet); a restart is confirmed when a seq that is 0, or lies far below the
// newest, is followed by its successor, as the pairing rule confirms a plant restart
// (pipeline/sample_pairer.hpp). A far leap ahead is confirmed the same way before it becomes the
// newest (LeapGuard). Not thread-safe.

#include <cstdint>
#include <optional>

#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

class RestartWatch {
 public:
  /// `newest`: the seq the stream is known to have reached (−1: nothing yet).
  explicit RestartWatch(int64_t newest = -1) : newest_(newest) {}

  /// Takes the arrival of `seq`; true when it confirms a restart (the stream goes on from it).
  bool Next(int64_t seq) {
    if (seq < 0) return false;
    if (seq > newest_) {
      if (leaps_.Check(seq, newest_) != LeapGuard::Verdict::kAccept) return false;
      newest_ = seq;
      candidate_.reset();  // the old numbering goes on: whatever lay below it was stale
      return false;
    }
    if (candidate_ && seq == *candidate_ + 1) {
      newest_ = seq;
      candidate_.reset();
      return true;
    }
    if (seq == 0 || seq + kConfirmLeap < newest_) candidate_ = seq;
    return false;
  }

  int64_t newest() const { return newest_; }

 private:
  int64_t newest_;
  std::optional<int64_t> candidate_;  // a seq that may begin a new numbering
  LeapGuard leaps_;
};

}  // namespace odonata::pipeline

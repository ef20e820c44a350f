#pragma once
// The sequence rule of a stream with one message per sample (any vehicle's signals_t,
// docs/lcm.md §14): which arrival is the next sample, which opens a gap, which starts the run
// again and which is dropped. The identifier and the log export both follow it, so a log exported
// to CSV holds exactly the samples, runs and gaps the identifier saw.

#include <cstdint>
#include <optional>
#include <string>

#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

class SampleSequence {
 public:
  struct Verdict {
    enum class Kind {
      kAccept,   ///< the next sample; `lost` seqs are missing just before it
      kRestart,  ///< the sender started over: a new run begins with this sample
      kDrop,     ///< not a sample to use: `why`
    };
    Kind kind = Kind::kAccept;
    int64_t lost = 0;
    std::string why;
  };

  /// Judges the arrival of `seq`. A restart is seq 0 after a higher one or, when that seq 0 was
  /// lost, two consecutive seqs far below the newest with no accepted sample between them (one
  /// stray old packet alone restarts nothing). A seq not after the newest is a duplicate or
  /// stale; a far leap is held until the next seq confirms it (LeapGuard).
  Verdict Next(int64_t seq) {
    const bool far_below = seq >= 0 && seq + kConfirmLeap < newest_;
    if ((seq == 0 && newest_ > 0) ||
        (far_below && restart_candidate_ && seq == *restart_candidate_ + 1)) {
      newest_ = seq;
      restart_candidate_.reset();
      return {Verdict::Kind::kRestart, 0, ""};
    }
    if (seq >= 0 && seq <= newest_) {
      if (far_below) restart_candidate_ = seq;
      return Drop("seq " + std::to_string(seq) + " is not after the newest, " +
                  std::to_string(newest_) +
                  " (a duplicate or stale sample, or a restart that the next seq confirms)");
    }
    std::string leap = leaps_.Problem("seq", seq, newest_);
    if (!leap.empty()) return Drop(std::move(leap));
    const int64_t lost = newest_ >= 0 ? seq - newest_ - 1 : 0;
    newest_ = seq;
    restart_candidate_.reset();  // a genuine sample came in between: no restart to confirm
    return {Verdict::Kind::kAccept, lost, ""};
  }

  int64_t newest() const { return newest_; }

 private:
  static Verdict Drop(std::string why) { return {Verdict::Kind::kDrop, 0, std::move(why)}; }

  int64_t newest_ = -1;
  std::optional<int64_t> restart_candidate_;  // a seq far below the newest, awaiting its next
  LeapGuard leaps_;
};

}  // namespace odonata::pipeline

#pragma once
// The sequence rule of a stream with one message per sample (any vehicle's signals_t,
// docs/lcm.md §14): which arrival is the next sample, which opens a gap, which starts the run
// again and which is dropped. The identifier and the log export both follow it, so a log exported
// to CSV holds exactly the samples, runs and gaps the identifier saw.

#include <cstdint>
#include <string>

#include "sequence/run_start.hpp"

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

  /// Judges the arrival of `seq` by the run rule (run_start.hpp) without confirmation: a seq 0
  /// after a higher one restarts the run, as do two consecutive seqs far below the newest (that
  /// seq 0 was lost; one stray old packet alone restarts nothing). A seq not after the newest is
  /// a duplicate or stale; a far leap is held until the next seq confirms it.
  Verdict Next(int64_t seq) {
    const int64_t before = run_.newest();
    RunVerdict v = run_.Next(seq, seq == 0);
    switch (v.kind) {
      case RunVerdict::Kind::kNext:
        return {Verdict::Kind::kAccept, before >= 0 ? seq - before - 1 : 0, ""};
      case RunVerdict::Kind::kRestart:
        return {Verdict::Kind::kRestart, 0, ""};
      case RunVerdict::Kind::kRefused:
        return Drop(std::move(v.why));
      case RunVerdict::Kind::kCandidate:
      case RunVerdict::Kind::kOlder:
        break;
    }
    return Drop("seq " + std::to_string(seq) + " is not after the newest, " +
                std::to_string(before) +
                " (a duplicate or stale sample, or a restart that the next seq confirms)");
  }

  int64_t newest() const { return run_.newest(); }

 private:
  static Verdict Drop(std::string why) { return {Verdict::Kind::kDrop, 0, std::move(why)}; }

  RunStart run_{kSignalSamples};
};

}  // namespace odonata::pipeline

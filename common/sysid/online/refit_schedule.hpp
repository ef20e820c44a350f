#pragma once
// When the online identifier refits, and on how many samples (docs/identifier.md §6.3): counts of
// samples learned, never times, so that a lockstep run and odonata-fit's replay refit alike.

#include <cstdint>

namespace odonata::sysid {

/// When the online learner refits (counts of samples learned, 1-based).
struct RefitSchedule {
  int64_t first = 0;  ///< the first refit starts after this many samples; 0: never refit
  int64_t every = 0;  ///< then at 2×, 4×, … first below this, then at every multiple of it
  /// The identifier's default: 10 s, 20 s, 40 s, then every 60 s at 100 Hz (docs/identifier.md
  /// §6.3; a struct left as it is never refits, as odonata-fit's own default).
  static RefitSchedule IdentifierDefault() {
    RefitSchedule s;
    s.first = 1000;
    s.every = 6000;
    return s;
  }
  /// The samples kept for a refit: 2 min at 100 Hz, so the closing refit of a flight of a minute
  /// or two sees all of it, as odonata-fit would. With 6 000, the closing refits of 70 s flights
  /// (tail-sitter, Flapper; training files) saw 5 500 of their 7 000 samples and chose models
  /// far from odonata-fit's on the same flight (docs/identifier.md §6.3).
  int64_t buffer = 12000;
  /// The share of `buffer` that may hold blocks spread over everything learned before the most
  /// recent samples (docs/identifier.md §6.3): a long record's refit still sees its whole range of
  /// operation, not the last minute only. 0: the most recent `buffer` samples.
  double history = 0.5;
  /// Blocks are history·buffer / kHistoryBlocks samples: three to six of them are kept.
  static constexpr int64_t kHistoryBlocks = 6;
  /// Shorter blocks would be mostly lags and windows cut short: the archive is off below this.
  static constexpr int64_t kShortestHistoryBlock = 100;
  /// Samples in one archived block; 0 when the archive is off.
  int64_t HistoryBlock() const;
  /// The fewest most recent samples the buffer keeps whole.
  int64_t RecentSamples() const { return buffer - kHistoryBlocks * HistoryBlock(); }
  /// When learning stops (a freeze, the end of a replayed file), the refit in flight lands and
  /// one more refit on the samples kept closes learning.
  bool at_freeze = true;
  /// Threads a refit trains its candidates on (SelectionOptions::threads): one leaves the other
  /// cores to the services beside it; the model is the same whatever the count.
  unsigned threads = 1;
  /// K > 1: a refit's selection scores and chooses K steps ahead (SelectionOptions::horizon, as
  /// odonata-fit --horizon) — for a loop that integrates, whose free run drifts for any model;
  /// 0: free run, as odonata-fit's default (docs/identifier.md §6.3).
  int horizon = 0;
  bool enabled() const { return first > 0 && buffer > 0; }
  /// True when a refit starts after sample number `learned`.
  bool Due(int64_t learned) const;
};

}  // namespace odonata::sysid

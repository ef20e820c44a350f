#pragma once
// Where a numbered stream's run begins again: the one rule every receiver follows — the
// identifier's pairing of DI-MAV states (pipeline/sample_pairer.hpp) and its signals_t samples
// (sample_sequence.hpp), the logger's receipts (written_run_marks.hpp), the log export (which
// pairs and sequences as the identifier does) and the generator's watch on a real-time plant.
//
// A run's first message is seq 0 flagged as a start by its sender (a plant's fresh state 0, whose
// command_seq is −1; a vehicle's signals_t seq 0). Mid-run, a start is, by option:
//   - with `confirm`, only a candidate until its successor (seq 1) arrives — or, with
//     `repeat_confirms`, the start again (a restarted lockstep plant repeats its state 0 while
//     nothing commands it): one stale or forged packet must not cut a run in two. With
//     `at_once_after_start`, a start right after a run's start (newest ≤ 1) restarts at once:
//     there is hardly a run to protect, and a resent seq 1 of the old run could not tell the new
//     run from it (the identifier's pairing; a recorder keeps the candidate instead, so a late
//     copy of the idle state 0 cannot move its receipts back);
//   - without `confirm`, taken at once (signals_t: nothing repeats a vehicle's seq 0, and a lost
//     seq 1 would leave the new run unheard).
// With `far_below`, a seq more than kConfirmLeap below the newest followed by its successor is a
// restart whose start was lost — not where resends reach back further than that (lockstep
// states, kLockstepResendReach). A seq beyond the newest drops any candidate (the old run goes
// on), and one that leaps more than kConfirmLeap ahead is held until the next confirms it
// (LeapGuard). Not thread-safe.
//
// The receivers' settings, each named below: DI-MAV states paired by the identifier and the
// export (kPairedStates), recorded by the logger (kRecordedStates), watched in real time by the
// generator (kRealtimeStates), and signals_t samples (kSignalSamples).

#include <cstdint>
#include <optional>
#include <string>

#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

struct RunStartOptions {
  bool confirm = true;               ///< a start mid-run waits for its successor
  bool repeat_confirms = true;       ///< … or for itself again
  bool at_once_after_start = false;  ///< with newest ≤ 1 a start restarts at once
  bool far_below = false;            ///< two consecutive seqs far below the newest restart
};

inline constexpr RunStartOptions kPairedStates{true, true, true, false};
inline constexpr RunStartOptions kRecordedStates{true, true, false, false};
inline constexpr RunStartOptions kRealtimeStates{true, false, false, true};
inline constexpr RunStartOptions kSignalSamples{false, false, false, true};

/// What an arrival means for the run.
struct RunVerdict {
  enum class Kind {
    kNext,       ///< beyond the newest: the run goes on (`dropped_candidate`: a start was stale)
    kOlder,      ///< not beyond the newest: a resend, duplicate or stale seq (the caller's rules)
    kCandidate,  ///< a start (or a seq far below) held until confirmed: not the run's, yet
    kRestart,    ///< the run begins again: from the held candidate (`from_candidate`), else here
    kRefused,    ///< negative, or a leap held or refused (`why`): drop it, nothing changed
  };
  Kind kind = Kind::kNext;
  bool dropped_candidate = false;
  bool from_candidate = false;
  std::string why;
};

class RunStart {
 public:
  /// `newest`: the seq the stream is known to have reached (−1: nothing yet).
  explicit RunStart(RunStartOptions options = {}, int64_t newest = -1)
      : options_(options), newest_(newest) {}

  /// Judges the arrival of `seq`; `start`: its sender flags it as a run's first message.
  /// `what` names the stream in a refusal ("state seq …").
  RunVerdict Next(int64_t seq, bool start, const std::string& what = "seq") {
    RunVerdict v;
    if (seq < 0 || seq > newest_) {
      v.why = leaps_.Problem(what, seq, newest_);
      if (!v.why.empty()) {
        v.kind = RunVerdict::Kind::kRefused;
        return v;
      }
      newest_ = seq;
      v.dropped_candidate = candidate_.has_value();
      candidate_.reset();
      return v;  // kNext
    }
    if (candidate_ &&
        (seq == *candidate_ + 1 || (options_.repeat_confirms && start && seq == *candidate_))) {
      newest_ = seq;
      candidate_.reset();
      v.kind = RunVerdict::Kind::kRestart;
      v.from_candidate = true;
      return v;
    }
    if (start && seq == 0 && newest_ > 0) {
      if (!options_.confirm || (options_.at_once_after_start && newest_ <= 1)) {
        newest_ = 0;
        candidate_.reset();
        v.kind = RunVerdict::Kind::kRestart;
        return v;
      }
      if (!candidate_) {
        candidate_ = 0;
        v.kind = RunVerdict::Kind::kCandidate;
        return v;
      }
    }
    if (options_.far_below && seq + kConfirmLeap < newest_) {
      candidate_ = seq;
      v.kind = RunVerdict::Kind::kCandidate;
      return v;
    }
    v.kind = RunVerdict::Kind::kOlder;
    return v;
  }

  /// The newest seq of the current run (−1: nothing yet).
  int64_t newest() const { return newest_; }
  /// The start held until confirmed, if any.
  const std::optional<int64_t>& candidate() const { return candidate_; }

 private:
  RunStartOptions options_;
  int64_t newest_;
  std::optional<int64_t> candidate_;
  LeapGuard leaps_;
};

}  // namespace odonata::pipeline

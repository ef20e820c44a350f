#pragma once
// What a lockstep consumer that keeps messages as they come (odonata-logger) may acknowledge:
// the newest state s such that every state up to s, every command up to s - 1 (which state s
// answers) and, once beat states are seen, every beat state up to s has arrived (docs/lcm.md §10).
//
// A plant run starts with a fresh state 0 (command_seq -1). Mid-run, one fresh state 0 is only a
// candidate new run, tracked beside the current one: a stale or forged state 0 must not move the
// receipts back, where the current run's states would then pile up behind a hole no resend
// fills. The candidate becomes the run once it holds states 0 and 1 (the plant answered a
// command of the new run), as a restarted run does; it is dropped once the current run has gone
// on by kStaleCandidate states (a restarted plant's old run goes nowhere), before its own holes
// could be given up.

#include <algorithm>
#include <cstdint>
#include <optional>

#include "sequence/contiguous_mark.hpp"
#include "sequence/lockstep_window.hpp"

namespace odonata {

class WrittenRunMarks {
 public:
  static constexpr int64_t kStaleCandidate = 32;
  static_assert(kStaleCandidate > pipeline::kMaxLockstepWindow,
                "a restarted run's first answer comes within one window");

  void OnState(int64_t seq, bool fresh) {
    if (fresh && seq == 0) {
      if (!run_fresh_ || run_.states.mark() < 0) {
        run_ = FreshRun();  // the first run seen from its start
        run_fresh_ = true;
      } else if (run_.states.mark() == 0) {
        // The plant repeats its state 0 until commanded (and after a RESET): the same start.
      } else {
        candidate_ = FreshRun();
        candidate_since_ = run_.states.mark();
      }
    }
    run_.states.Add(seq);
    if (candidate_ && run_.states.mark() > candidate_since_ + kStaleCandidate) candidate_.reset();
    if (!candidate_) return;
    candidate_->states.Add(seq);
    if (candidate_->states.mark() >= 1) {
      run_ = *candidate_;
      candidate_.reset();
    }
  }

  void OnCommand(int64_t seq) {
    run_.commands.Add(seq);
    if (candidate_) candidate_->commands.Add(seq);
  }

  void OnBeat(int64_t seq) {
    beats_seen_ = true;
    run_.beats.Add(seq);
    if (candidate_) candidate_->beats.Add(seq);
  }

  /// The newest state held with all it needs; -1 before any.
  int64_t held() const {
    int64_t held = std::min(run_.states.mark(), run_.commands.mark() + 1);
    if (beats_seen_) held = std::min(held, run_.beats.mark());
    return held;
  }

 private:
  struct Marks {
    ContiguousMark states, commands, beats;
  };
  // A run from its state 0 on: its commands and beat states count from 0 too.
  static Marks FreshRun() {
    Marks m;
    m.states.ExpectFrom(0);
    m.commands.ExpectFrom(0);
    m.beats.ExpectFrom(0);
    return m;
  }

  Marks run_;
  bool run_fresh_ = false;  // run_ started at a fresh state 0 (not joined mid-run)
  std::optional<Marks> candidate_;
  int64_t candidate_since_ = -1;  // the current run's state mark when the candidate came
  bool beats_seen_ = false;
};

}  // namespace odonata

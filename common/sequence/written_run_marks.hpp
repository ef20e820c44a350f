#pragma once
// What a lockstep consumer that keeps messages as they come (odonata-logger) may acknowledge:
// the newest state s such that every state up to s, every command up to s - 1 (which state s
// answers) and, once beat states are seen, every beat state up to s has arrived (docs/lcm.md §10).
//
// A plant run starts with a fresh state 0 (command_seq -1); where the run begins again is the
// run rule's (run_start.hpp, kRecordedStates: with confirmation, as the identifier pairs, and no
// restart at once right after the run's start, so a late copy of the idle state 0 cannot move
// the receipts back): mid-run, one fresh
// state 0 is only a candidate new run, tracked beside the current one — a stale or forged state 0
// must not move the receipts back, where the current run's states would then pile up behind a
// hole no resend fills. The candidate becomes the run once the plant answers a command of it
// (state 1), and is dropped once the current run goes on past its newest state.

#include <algorithm>
#include <cstdint>
#include <optional>

#include "sequence/contiguous_mark.hpp"
#include "sequence/run_start.hpp"

namespace odonata {

class WrittenRunMarks {
 public:
  void OnState(int64_t seq, bool fresh) {
    using Kind = pipeline::RunVerdict::Kind;
    const pipeline::RunVerdict v = run_start_.Next(seq, fresh && seq == 0);
    switch (v.kind) {
      case Kind::kNext:
        if (v.dropped_candidate) candidate_.reset();
        if (fresh && seq == 0) run_ = FreshRun();  // the first run seen from its start
        break;
      case Kind::kCandidate:
        candidate_ = FreshRun();
        break;
      case Kind::kRestart:
        run_ = v.from_candidate && candidate_ ? *candidate_ : FreshRun();
        candidate_.reset();
        break;
      case Kind::kRefused:
        return;  // a leap held or refused: written, but it moves no receipt
      case Kind::kOlder:
        break;
    }
    run_.states.Add(seq);
    if (candidate_) candidate_->states.Add(seq);
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

  pipeline::RunStart run_start_{pipeline::kRecordedStates};
  Marks run_;
  std::optional<Marks> candidate_;
  bool beats_seen_ = false;
};

}  // namespace odonata

#pragma once
// How far a sample's seq may jump ahead of the newest one a receiver has seen. A real gap (lost
// packets, a paused generator) is short; a seq that leaps by more than this is a foreign or
// corrupt message, and accepting it would make every genuine message after it look stale, so
// one bad packet would stall the run.

#include <cstdint>

namespace odonata::pipeline {

/// ≈ 2.8 h at 100 Hz, or 100 s of lockstep at 10 kHz.
inline constexpr int64_t kMaxSeqJump = 1'000'000;

/// True when `seq` is non-negative and at most kMaxSeqJump beyond `newest` (−1 when nothing has
/// been seen yet, so a first message must lie within [0, kMaxSeqJump)).
constexpr bool SeqWithinWindow(int64_t seq, int64_t newest) {
  return seq >= 0 && seq - (newest < 0 ? -1 : newest) <= kMaxSeqJump;
}

}  // namespace odonata::pipeline

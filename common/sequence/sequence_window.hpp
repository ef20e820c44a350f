#pragma once
// How far a sample's seq may jump ahead of the newest one a receiver has seen. A real gap (lost
// packets, a paused generator) is short; a seq that leaps by more than this is a foreign or
// corrupt message, and accepting it would make every genuine message after it look stale, so
// one bad packet would stall the run.

#include <cstdint>
#include <optional>
#include <string>

namespace odonata::pipeline {

/// ≈ 2.8 h at 100 Hz, or 100 s of lockstep at 10 kHz.
inline constexpr int64_t kMaxSeqJump = 1'000'000;

/// True when `seq` is non-negative and at most kMaxSeqJump beyond `newest` (−1 when nothing has
/// been seen yet, so a first message must lie within [0, kMaxSeqJump)).
constexpr bool SeqWithinWindow(int64_t seq, int64_t newest) {
  return seq >= 0 && seq - (newest < 0 ? -1 : newest) <= kMaxSeqJump;
}

/// Leaps beyond this many sequence numbers must be confirmed before a receiver moves its window.
/// Lockstep never skips (the generator resends), and real-time losses are a few samples: a
/// forged seq up to this far ahead costs at most this many genuine messages.
inline constexpr int64_t kConfirmLeap = 16;

/// Holds back a seq that leaps more than kConfirmLeap past the newest until the next seq after it
/// arrives (a plant's next state, a generator's next command): one forged in-window packet, or
/// the same one resent, then cannot make every genuine message after it look stale. A genuine
/// long gap costs one message (the one that opened it); lockstep never leaps after its first
/// command (the generator resends instead). Not thread-safe.
class LeapGuard {
 public:
  enum class Verdict {
    kAccept,  ///< use it
    kHold,    ///< a leap awaiting confirmation: drop it for now (the receiver's window stays)
    kReject,  ///< negative, or beyond kMaxSeqJump
  };

  /// `newest`: the receiver's newest seq (−1: none yet, and then any in-window seq is accepted).
  Verdict Check(int64_t seq, int64_t newest) {
    if (!SeqWithinWindow(seq, newest)) return Verdict::kReject;
    if (newest < 0 || seq - newest <= kConfirmLeap) return Verdict::kAccept;
    if (candidate_ && seq == *candidate_ + 1) {
      candidate_.reset();
      return Verdict::kAccept;
    }
    candidate_ = seq;
    return Verdict::kHold;
  }

  /// Check() in a receiver's words: empty to use `seq`, else why it is dropped ("<what> seq …").
  std::string Problem(const std::string& what, int64_t seq, int64_t newest) {
    switch (Check(seq, newest)) {
      case Verdict::kAccept:
        return "";
      case Verdict::kHold:
        return what + " seq " + std::to_string(seq) + " leaps " + std::to_string(seq - newest) +
               " past the newest, " + std::to_string(newest) +
               ": held until the next seq confirms it (a lone or resent forged packet never is)";
      case Verdict::kReject:
        break;
    }
    return what + " seq " + std::to_string(seq) + " is negative or leaps more than " +
           std::to_string(kMaxSeqJump) + " past the newest, " + std::to_string(newest);
  }

 private:
  std::optional<int64_t> candidate_;
};

}  // namespace odonata::pipeline

#pragma once
// The signal generator's side of the lockstep protocol, without transport: which message to send
// next given the states that arrive and the timeouts that expire.
//
//   [reset] → wait for state 0 (command_seq -1) → send command 0 → wait for state 1 answering
//   command 0 → send command 1 → … → state N answering command N-1 ⇒ finished.
// A timeout resends what is awaited (RESET, or command k); after max_resends consecutive resends
// without progress the run fails.
//
// Lossless: with consumers (identifier, logger: ack_t receipts), an answer counts only once every
// consumer has acknowledged its state, so the next command waits for the slowest of them; a
// consumer that lost the state or its command gets both again from the resend of command k
// (the plant re-publishes its answer). A consumer that acknowledges nothing for max_resends
// resends fails the run: it would otherwise miss samples silently.

#include <cstdint>
#include <map>
#include <string>

namespace odonata::pipeline {

/// What the caller must do next.
struct SequencerAction {
  enum class Kind {
    kNone,         ///< nothing: keep waiting (and keep the timeout running)
    kSendReset,    ///< send RESET to the plant, then wait (restart the timeout)
    kSendCommand,  ///< send command `seq`, then wait (restart the timeout)
    kFinished,     ///< every command has been answered
    kFailed,       ///< give up: `message` says why
  };
  Kind kind{Kind::kNone};
  /// kFailed: why.
  enum class Failure { kNone, kNoAnswer, kRestarted, kDiverged, kConsumerLost };
  int64_t seq{-1};                  ///< kSendCommand: the command to send
  bool resend{};                    ///< kSendReset / kSendCommand: after a timeout
  Failure failure{Failure::kNone};  ///< kFailed
  std::string message;              ///< kFailed
};

/// Lockstep protocol state machine. Not thread-safe.
class LockstepSequencer {
 public:
  enum class Phase { kIdle, kAwaitingInitial, kAwaitingAnswer, kFinished, kFailed };

  /// @param command_count N ≥ 1 commands to send (seq 0 … N-1).
  /// @param reset_plant start by sending RESET; otherwise wait for a fresh state 0 as it is.
  /// @param max_resends consecutive timeouts allowed per awaited message (≥ 0).
  /// @param restart_confirm_timeouts how many timeouts a fresh state 0 mid-run stays a suspicion
  ///        (nothing resent meanwhile): a restarted plant, left uncommanded, repeats its state 0
  ///        and so confirms it; a lone forged or stale one is forgotten and the run goes on.
  /// @throws std::invalid_argument for command_count < 1, max_resends < 0 or
  ///         restart_confirm_timeouts < 1.
  LockstepSequencer(int64_t command_count, bool reset_plant, int max_resends,
                    int restart_confirm_timeouts = 3);

  /// First action: kSendReset, or kNone (wait for state 0).
  SequencerAction Start();
  /// A state arrived. `diverged` is its status (the plant stopped: the run cannot go on).
  SequencerAction OnState(int64_t seq, int64_t command_seq, bool diverged);
  /// The awaited state did not come in time.
  SequencerAction OnTimeout();

  /// From now on, states count only once `instance` has acknowledged them. A consumer added
  /// mid-run catches up from the resend of the awaited command.
  SequencerAction AddConsumer(const std::string& instance);
  /// Stops waiting for `instance` (it stopped cleanly); may release the next command.
  SequencerAction RemoveConsumer(const std::string& instance);
  /// `instance` holds state `state_seq` and all it needs (ack_t). Unknown instances are ignored.
  SequencerAction OnAck(const std::string& instance, int64_t state_seq);
  /// Holds command 0 until ReleaseStart() (while the generator discovers its consumers).
  void HoldStart() { start_held_ = true; }
  SequencerAction ReleaseStart();

  Phase phase() const { return phase_; }
  /// The command whose answer is awaited (or the next to send).
  int64_t current() const { return current_; }
  int64_t command_count() const { return command_count_; }
  /// Resends in total (each is a lost message or a slow plant).
  int64_t total_resends() const { return total_resends_; }
  /// Of those, resends because a consumer had not acknowledged a state the plant had answered.
  int64_t ack_resends() const { return ack_resends_; }
  /// The consumers waited for, with the newest state each acknowledged.
  const std::map<std::string, int64_t>& consumers() const { return consumers_; }

 private:
  SequencerAction Fail(SequencerAction::Failure failure, std::string message);
  // The state the current step waits for: 0 before command 0, else the answer to current_.
  int64_t Awaited() const { return phase_ == Phase::kAwaitingInitial ? 0 : current_ + 1; }
  bool Acknowledged(int64_t state_seq) const;
  std::string Laggards(int64_t state_seq) const;
  // Moves on when the awaited state arrived, every consumer has it and the start is not held.
  SequencerAction TryAdvance();

  int64_t command_count_;
  bool reset_plant_;
  int max_resends_;
  int restart_confirm_timeouts_;
  int restart_suspected_for_ = -1;  // timeouts since a fresh state 0 mid-run (-1: none)
  Phase phase_ = Phase::kIdle;
  int64_t current_ = 0;
  int resends_ = 0;  // consecutive, for the message awaited now
  int64_t total_resends_ = 0;
  int64_t ack_resends_ = 0;
  bool received_ = false;  // the awaited state arrived (acknowledgements may still be missing)
  bool start_held_ = false;
  std::map<std::string, int64_t> consumers_;  // instance -> newest acknowledged state
};

}  // namespace odonata::pipeline

#pragma once
// The signal generator's side of the lockstep protocol, without transport: which messages to send
// next given the states that arrive and the timeouts that expire.
//
//   [reset] → wait for state 0 (command_seq -1) → send commands 0 … W-1 → as state k + 1
//   answering command k arrives, the window slides and command k + W goes out → … → state N
//   answering command N-1 ⇒ finished.
// With a window of W = 1 that is one command at a time. Larger windows keep W commands in
// flight, so the hops of one sample overlap with those of the next; the plant applies commands
// strictly in seq order (plant_session.hpp), so the run is the same for every W.
// A timeout resends what is awaited (RESET, or every command from the oldest unconfirmed one on);
// after max_resends consecutive resends without progress the run fails.
//
// Lossless: with consumers (identifier, logger: ack_t receipts), a state counts as confirmed only
// once every consumer has acknowledged it, and the window slides over confirmed states only, so
// the run waits for the slowest consumer; a consumer that lost a state or a command gets it
// again from the resend (the plant re-publishes its answers). A consumer that acknowledges
// nothing for max_resends resends fails the run: it would otherwise miss samples silently.

#include <cstdint>
#include <map>
#include <set>
#include <string>

#include "sequence/lockstep_window.hpp"
#include "sequence/refit_patience.hpp"

namespace odonata::pipeline {

/// What the caller must do next.
struct SequencerAction {
  enum class Kind {
    kNone,         ///< nothing: keep waiting (and keep the timeout running)
    kSendReset,    ///< send RESET to the plant, then wait (restart the timeout)
    kSendCommand,  ///< send commands `seq` … `seq` + `count` - 1, then wait (restart the timeout)
    kFinished,     ///< every command has been answered
    kFailed,       ///< give up: `message` says why
  };
  Kind kind{Kind::kNone};
  /// kFailed: why.
  enum class Failure { kNone, kNoAnswer, kRestarted, kDiverged, kConsumerLost };
  int64_t seq{-1};   ///< kSendCommand: the first command to send
  int64_t count{1};  ///< kSendCommand: how many, in seq order
  /// A state was confirmed (the window slid): restart the timeout even if nothing is sent.
  bool progressed{};
  bool resend{};                    ///< kSendReset / kSendCommand: after a timeout
  Failure failure{Failure::kNone};  ///< kFailed
  std::string message;              ///< kFailed
};

/// Lockstep protocol state machine. Not thread-safe.
class LockstepSequencer {
 public:
  enum class Phase { kIdle, kAwaitingInitial, kAwaitingAnswer, kFinished, kFailed };

  /// Largest window (sequence/lockstep_window.hpp).
  static constexpr int kMaxWindow = static_cast<int>(kMaxLockstepWindow);
  /// How far back a resend may reach: as far as the plant keeps its answers.
  static constexpr int64_t kResendReach = kLockstepResendReach;

  /// @param command_count N ≥ 1 commands to send (seq 0 … N-1).
  /// @param reset_plant start by sending RESET; otherwise wait for a fresh state 0 as it is.
  /// @param max_resends consecutive timeouts allowed per awaited message (≥ 0).
  /// @param restart_confirm_timeouts how many timeouts a fresh state 0 mid-run stays a suspicion
  ///        (nothing resent meanwhile): a restarted plant, left uncommanded, repeats its state 0
  ///        and so confirms it; a lone forged or stale one is forgotten and the run goes on.
  /// @param window commands in flight, 1 … kMaxWindow.
  /// @throws std::invalid_argument for command_count < 1, max_resends < 0,
  ///         restart_confirm_timeouts < 1 or a window outside 1 … kMaxWindow.
  LockstepSequencer(int64_t command_count, bool reset_plant, int max_resends,
                    int restart_confirm_timeouts = 3, int window = 1);

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
  /// `instance` says (heartbeat state "refitting") that it is landing a scheduled refit and
  /// acknowledges nothing until it has: while every consumer the run waits for is busy, a
  /// timeout resends nothing and costs none of max_resends, for at most max_busy_timeouts() in a
  /// row (a forged or stuck "busy" cannot hold the run for ever). Unknown instances are ignored.
  void SetBusy(const std::string& instance, bool busy);
  /// The default bound: 10 min at the default 200 ms timeout.
  static constexpr int kMaxBusyTimeouts = 3000;
  /// Timeouts in a row a busy consumer may cost before the run fails (≥ 0).
  void set_max_busy_timeouts(int n) { patience_.set_max_timeouts(n); }
  int max_busy_timeouts() const { return patience_.max_timeouts(); }
  /// `instance` holds state `state_seq` and all it needs (ack_t). Unknown instances are ignored,
  /// and so is a receipt for a state beyond the answer to the newest command sent.
  SequencerAction OnAck(const std::string& instance, int64_t state_seq);
  /// Holds command 0 until ReleaseStart() (while the generator discovers its consumers).
  void HoldStart() { start_held_ = true; }
  SequencerAction ReleaseStart();
  /// Sends no command from `seq` on until ReleaseHold(): the run stands still with every state up
  /// to `seq` confirmed, so whatever happens meanwhile (a test's fault) lands at a definite sample.
  /// @throws std::invalid_argument unless 1 ≤ seq < command_count.
  void HoldAt(int64_t seq);
  SequencerAction ReleaseHold();
  /// Every command before the hold is confirmed and nothing is in flight.
  bool holding() const {
    return hold_at_ >= 0 && phase_ == Phase::kAwaitingAnswer && current_ == hold_at_;
  }

  Phase phase() const { return phase_; }
  /// The oldest command whose answer is not confirmed yet (or the next to send).
  int64_t current() const { return current_; }
  /// Commands sent so far (each once; resends not counted).
  int64_t sent() const { return sent_; }
  int window() const { return window_; }
  int64_t command_count() const { return command_count_; }
  /// Resends in total (each is a lost message or a slow plant).
  int64_t total_resends() const { return total_resends_; }
  /// Of those, resends because a consumer had not acknowledged a state the plant had answered.
  int64_t ack_resends() const { return ack_resends_; }
  /// Timeouts spent waiting for busy consumers (SetBusy), nothing resent.
  int64_t busy_timeouts() const { return patience_.total(); }
  /// Of those, the ones in a row now, and who is waited for: what a stalled run should say.
  int busy_in_a_row() const { return patience_.in_a_row(); }
  /// The patience with consumers landing a refit (its notice, its counts).
  const RefitPatience& patience() const { return patience_; }
  std::string Waited() const { return Laggards(Awaited()); }
  /// Receipts ignored because they acknowledged a state no command sent could have produced.
  int64_t impossible_acks() const { return impossible_acks_; }
  /// The consumers waited for, with the newest state each acknowledged.
  const std::map<std::string, int64_t>& consumers() const { return consumers_; }

 private:
  SequencerAction Fail(SequencerAction::Failure failure, std::string message);
  // The state the window waits for: 0 before command 0, else the answer to current_.
  int64_t Awaited() const { return phase_ == Phase::kAwaitingInitial ? 0 : current_ + 1; }
  // The newest state every consumer holds (the largest int64_t without consumers).
  int64_t LowestAck() const;
  bool Acknowledged(int64_t state_seq) const { return LowestAck() >= state_seq; }
  std::string Laggards(int64_t state_seq) const;
  // Every consumer that lacks `state_seq` is busy (and there is one).
  std::vector<std::string> LaggardNames(int64_t state_seq) const;
  // Confirms what the plant answered and every consumer acknowledged, then fills the window.
  SequencerAction TryAdvance();
  // Sends what the window (and the hold) allow beyond what was sent: `a` with the commands.
  SequencerAction FillWindow(SequencerAction a);

  int64_t command_count_;
  bool reset_plant_;
  int max_resends_;
  int restart_confirm_timeouts_;
  int restart_suspected_for_ = -1;  // timeouts since a fresh state 0 mid-run (-1: none)
  int window_;
  Phase phase_ = Phase::kIdle;
  int64_t current_ = 0;    // the oldest unconfirmed command: state current_ is confirmed
  int64_t sent_ = 0;       // commands 0 … sent_ - 1 have been sent
  int64_t answered_ = -1;  // the newest state the plant sent in answer to a command
  int resends_ = 0;        // consecutive, for the message awaited now
  int64_t total_resends_ = 0;
  int64_t ack_resends_ = 0;
  int64_t impossible_acks_ = 0;
  bool received_ = false;  // state 0 arrived (acknowledgements may still be missing)
  bool start_held_ = false;
  int64_t hold_at_ = -1;  // no command from here on until ReleaseHold() (-1: no hold)
  std::map<std::string, int64_t> consumers_;  // instance -> newest acknowledged state
  RefitPatience patience_{kMaxBusyTimeouts};  // consumers landing a refit
};

}  // namespace odonata::pipeline

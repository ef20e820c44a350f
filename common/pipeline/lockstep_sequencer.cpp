#include "pipeline/lockstep_sequencer.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace odonata::pipeline {

LockstepSequencer::LockstepSequencer(int64_t command_count, bool reset_plant, int max_resends,
                                     int restart_confirm_timeouts, int window)
    : command_count_(command_count),
      reset_plant_(reset_plant),
      max_resends_(max_resends),
      restart_confirm_timeouts_(restart_confirm_timeouts),
      window_(window) {
  if (window < 1 || window > kMaxWindow)
    throw std::invalid_argument("window must be 1 … " + std::to_string(kMaxWindow));
  if (command_count < 1) throw std::invalid_argument("lockstep run without commands");
  if (max_resends < 0) throw std::invalid_argument("max_resends must be >= 0");
  if (restart_confirm_timeouts < 1)
    throw std::invalid_argument("restart_confirm_timeouts must be >= 1");
}

SequencerAction LockstepSequencer::Start() {
  phase_ = Phase::kAwaitingInitial;
  current_ = 0;
  sent_ = 0;
  answered_ = -1;
  resends_ = 0;
  received_ = false;
  SequencerAction a;
  if (reset_plant_) a.kind = SequencerAction::Kind::kSendReset;
  return a;
}

SequencerAction LockstepSequencer::Fail(SequencerAction::Failure failure, std::string message) {
  phase_ = Phase::kFailed;
  SequencerAction a;
  a.kind = SequencerAction::Kind::kFailed;
  a.failure = failure;
  a.message = std::move(message);
  return a;
}

int64_t LockstepSequencer::LowestAck() const {
  int64_t lowest = std::numeric_limits<int64_t>::max();
  for (const auto& [instance, acked] : consumers_) lowest = std::min(lowest, acked);
  return lowest;
}

void LockstepSequencer::SetBusy(const std::string& instance, bool busy) {
  if (consumers_.count(instance) == 0) return;
  patience_.SetBusy(instance, busy);
}

std::vector<std::string> LockstepSequencer::LaggardNames(int64_t state_seq) const {
  std::vector<std::string> names;
  for (const auto& [instance, acked] : consumers_)
    if (acked < state_seq) names.push_back(instance);
  return names;
}

std::string LockstepSequencer::Laggards(int64_t state_seq) const {
  std::string names;
  for (const auto& [instance, acked] : consumers_) {
    if (acked >= state_seq) continue;
    if (!names.empty()) names += ", ";
    names += "'" + instance + "' (newest acknowledged: " + std::to_string(acked) + ")";
  }
  return names;
}

SequencerAction LockstepSequencer::TryAdvance() {
  SequencerAction a;
  if (phase_ == Phase::kAwaitingInitial) {
    if (!received_ || !Acknowledged(0) || start_held_) return a;
    phase_ = Phase::kAwaitingAnswer;
    current_ = 0;
    resends_ = 0;
    patience_.Reset();
    a.progressed = true;
  } else if (phase_ == Phase::kAwaitingAnswer) {
    // The newest state the plant answered and every consumer holds; the plant answers in seq
    // order, so everything before it was answered too.
    const int64_t confirmed = std::min(answered_, LowestAck());
    if (confirmed <= current_) return a;
    current_ = confirmed;
    resends_ = 0;
    patience_.Reset();
    a.progressed = true;
    if (current_ == command_count_) {
      phase_ = Phase::kFinished;
      a.kind = SequencerAction::Kind::kFinished;
      return a;
    }
  } else {
    return a;
  }
  return FillWindow(a);
}

SequencerAction LockstepSequencer::FillWindow(SequencerAction a) {
  int64_t end = std::min(current_ + window_, command_count_);
  if (hold_at_ >= 0) end = std::min(end, hold_at_);
  if (sent_ < end) {
    a.kind = SequencerAction::Kind::kSendCommand;
    a.seq = sent_;
    a.count = end - sent_;
    sent_ = end;
  }
  return a;
}

SequencerAction LockstepSequencer::AddConsumer(const std::string& instance) {
  consumers_.emplace(instance, -1);
  return SequencerAction{};  // adding never releases anything
}

SequencerAction LockstepSequencer::RemoveConsumer(const std::string& instance) {
  consumers_.erase(instance);
  patience_.Forget(instance);
  return TryAdvance();
}

SequencerAction LockstepSequencer::OnAck(const std::string& instance, int64_t state_seq) {
  const auto it = consumers_.find(instance);
  if (it == consumers_.end()) return SequencerAction{};
  if (phase_ == Phase::kAwaitingInitial) {
    // Before command 0 a consumer still acknowledges its previous run (the logger takes a fresh
    // state 0 for a new run only once the plant answers a command of it): any receipt says it
    // is there, and holds no more than state 0 of this run.
    state_seq = std::min<int64_t>(state_seq, 0);
  } else if (state_seq > sent_) {
    // No state beyond the answer to the newest command sent exists yet: a receipt for one is
    // forged, or a consumer's previous run, and believing it would slide the window past a
    // consumer that holds nothing.
    ++impossible_acks_;
    return SequencerAction{};
  }
  // A consumer that restarted acknowledges from scratch: its newest receipt is the truth.
  it->second = state_seq;
  return TryAdvance();
}

SequencerAction LockstepSequencer::ReleaseStart() {
  start_held_ = false;
  return TryAdvance();
}

void LockstepSequencer::HoldAt(int64_t seq) {
  if (seq < 1 || seq >= command_count_)
    throw std::invalid_argument("hold at command " + std::to_string(seq) + ": must be 1 … " +
                                std::to_string(command_count_ - 1));
  hold_at_ = seq;
}

SequencerAction LockstepSequencer::ReleaseHold() {
  hold_at_ = -1;
  if (phase_ != Phase::kAwaitingAnswer) return TryAdvance();
  // Nothing new is confirmed: what the hold kept back goes out now, and the timeout restarts.
  SequencerAction a;
  a.progressed = true;
  return FillWindow(a);
}

SequencerAction LockstepSequencer::OnState(int64_t seq, int64_t command_seq, bool diverged) {
  SequencerAction a;
  if (phase_ == Phase::kAwaitingInitial) {
    if (seq != 0 || command_seq != -1) return a;  // an old run's state, or another generator's
    received_ = true;
    return TryAdvance();
  }
  if (phase_ != Phase::kAwaitingAnswer) return a;
  if (seq == 0 && command_seq == -1 && answered_ > 0) {
    // The plant answered a command already, so this is not a late copy of state 0: the plant
    // restarted (or someone reset it) and the rest of the run would start from scratch unseen —
    // or one forged packet says so. Suspect first; a second fresh state 0 (a restarted plant
    // repeats it while nothing commands it) confirms.
    if (restart_suspected_for_ < 0) {
      restart_suspected_for_ = 0;
      return a;
    }
    return Fail(SequencerAction::Failure::kRestarted,
                "the plant restarted (fresh state 0, twice) while it was answering command " +
                    std::to_string(current_));
  }
  // Answers to commands not sent (another generator's, or stale) and resends are no news.
  if (seq != command_seq + 1 || command_seq < 0 || command_seq >= sent_) return a;
  restart_suspected_for_ = -1;  // the plant answers: whatever said state 0 was not it
  if (diverged) {
    return Fail(SequencerAction::Failure::kDiverged, "the plant diverged while applying command " +
                                                         std::to_string(command_seq) +
                                                         " (its divergence policy is stop)");
  }
  if (seq <= answered_) return a;
  answered_ = seq;
  return TryAdvance();
}

SequencerAction LockstepSequencer::OnTimeout() {
  SequencerAction a;
  if (phase_ != Phase::kAwaitingInitial && phase_ != Phase::kAwaitingAnswer) return a;
  if (phase_ == Phase::kAwaitingInitial && received_ && start_held_) return a;  // discovering
  if (holding()) return a;  // nothing in flight, nothing awaited
  if (restart_suspected_for_ >= 0) {
    // Resending now would command a restarted plant and hide its restart: wait for it to repeat
    // its state 0, and only then give up the suspicion.
    if (++restart_suspected_for_ < restart_confirm_timeouts_) return a;
    restart_suspected_for_ = -1;
  }
  const bool acks_missing = phase_ == Phase::kAwaitingInitial
                                ? received_ && !Acknowledged(0)
                                : answered_ >= Awaited() && !Acknowledged(Awaited());
  // While only consumers landing a refit lack it, they have the messages or will get them from
  // the next resend once they are back: nothing is lost by waiting, and resending into a process
  // that is not reading helps nobody.
  if (!acks_missing) {
    patience_.Reset();
  } else {
    switch (patience_.OnTimeout(LaggardNames(Awaited()))) {
      case RefitPatience::Verdict::kWait:
        return a;
      case RefitPatience::Verdict::kSpent:
        return Fail(SequencerAction::Failure::kConsumerLost,
                    "no acknowledgement of state " + std::to_string(Awaited()) + " from " +
                        Laggards(Awaited()) + ", busy for " + std::to_string(patience_.in_a_row()) +
                        " timeouts in a row: it would miss samples");
      case RefitPatience::Verdict::kNotBusy:
        break;
    }
  }
  if (resends_ >= max_resends_) {
    if (acks_missing) {
      return Fail(SequencerAction::Failure::kConsumerLost,
                  "no acknowledgement of state " + std::to_string(Awaited()) + " from " +
                      Laggards(Awaited()) + " after " + std::to_string(resends_) +
                      " resends: it would miss samples");
    }
    if (phase_ == Phase::kAwaitingInitial) {
      return Fail(SequencerAction::Failure::kNoAnswer,
                  reset_plant_ ? "no fresh state 0 after RESET"
                               : "no fresh state 0 (seq 0, command_seq -1): start the plant anew "
                                 "or let the generator reset it");
    }
    return Fail(SequencerAction::Failure::kNoAnswer,
                "no answer (state " + std::to_string(current_ + 1) + ") to command " +
                    std::to_string(current_));
  }
  ++resends_;
  ++total_resends_;
  if (acks_missing) ++ack_resends_;
  a.resend = true;
  if (phase_ == Phase::kAwaitingInitial) {
    // Without a reset there is nothing to resend: waiting again is all there is to do.
    if (reset_plant_) a.kind = SequencerAction::Kind::kSendReset;
    return a;
  }
  // Everything in flight from the oldest unconfirmed command on: the plant answers the ones it
  // applied again and applies the rest, so one timeout repairs every hole in the window. A
  // consumer that restarted may hold less than what was confirmed before: from the answer it
  // lacks on, as far back as the plant still answers.
  const int64_t from =
      std::max({std::min(current_, LowestAck()), sent_ - kResendReach, int64_t{0}});
  a.kind = SequencerAction::Kind::kSendCommand;
  a.seq = from;
  a.count = sent_ - from;
  return a;
}

}  // namespace odonata::pipeline

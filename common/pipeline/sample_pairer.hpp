#pragma once
// The online identifier's pairing rule, without transport: which plant states, commands and
// beat states make sample k, when a sample is complete, when it is lost (a gap, never bridged)
// and when the plant restarted its run.
//
// Sample k joins
//   - state k: y(k), and state signals used as inputs;
//   - the command that state k + 1 answers (its command_seq, k in lockstep): u(k);
//   - beat state k: the beat averages up to t_k (odonata-sim's row k: `*_avg`);
//   - beat state k + 1: the command applied over [t_k, t_k+1) (`u_*_applied_rad`); its
//     command_seq must equal state k + 1's.
// exactly as odonata-logger export writes row k (log_export/log_csv_export.hpp). Sample k is
// complete once state k + 1, its command and the beat states it needs (PairingNeeds) have arrived;
// a state whose sample still lacks a message waits (up to kMaxPendingStates states), then the
// sample is lost.
//
// A missing state holds the states after it (up to kMaxStatesAfterHole, then its sample is lost):
// with a window of lockstep commands in flight, the states that overtook a lost one wait for its
// resend instead of turning it into a gap. A state or beat state that fills a hole is taken in
// whatever order it comes.
//
// Seq rules: a state or beat state whose seq is negative or leaps too far ahead
// (sequence_window.hpp), one older than the newest by more than kResendReach, and a second
// command with a used seq from another source are bad input (std::invalid_argument, nothing
// changes); an older state or beat state already held or used is a resend (ignored). Where the
// states' run begins again is the run rule's (sequence/run_start.hpp, with confirmation): a fresh
// state 0 (command_seq < 0) mid-run is only a *candidate* plant restart until the plant confirms
// it with its state 1 or a second fresh state 0. Then every message of the old run is forgotten,
// and the commands that came since the candidate are the new run's. A state newer than the old
// run's newest drops the candidate (the old run goes on; the commands kept aside are its own). A
// fresh beat state 0 starts the beat states afresh, and survives the state restart that follows
// it.
//
// State, Command and Beat are the message types (or stand-ins in tests): State and Beat need
// `seq` and `command_seq`, Command `seq` and `source`.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "sequence/lockstep_window.hpp"
#include "sequence/run_start.hpp"
#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

/// The beat states a sample needs besides its two states and its command, from the signals the
/// model uses. The command is always needed, whatever the signals: a sample is the plant's
/// answer to a command, so states published without one (a real-time plant idling before its
/// run) make no sample, as they make no row of odonata-logger export.
struct PairingNeeds {
  bool beat = false;       ///< beat state k (beat averages)
  bool next_beat = false;  ///< beat state k + 1 (the command applied over [t_k, t_k+1))
};

template <class State, class Command, class Beat>
class SamplePairer {
 public:
  static constexpr std::size_t kMaxCommands = 4096;     ///< commands kept for pairing
  static constexpr std::size_t kMaxBeats = 4096;        ///< beat states kept for pairing
  static constexpr std::size_t kMaxPendingStates = 64;  ///< states waiting before giving up
  /// States held after a missing one before its sample is given up. A lockstep generator keeps
  /// fewer commands than this in flight (odonata-signal --window ≤ 16), so a state lost in
  /// lockstep is resent before it is given up.
  static constexpr std::size_t kMaxStatesAfterHole = 32;
  static_assert(static_cast<int64_t>(kMaxStatesAfterHole) > kMaxLockstepWindow);
  /// How far back a resent state or beat state may lie behind the newest (as far as a
  /// generator's resend reaches); anything older is stale.
  static constexpr int64_t kResendReach = kLockstepResendReach;

  /// What became of the messages, in order.
  struct Event {
    enum class Kind {
      kSample,   ///< sample `index` is complete: state, and the optional messages it needs
      kGap,      ///< `lost` samples are lost: `what` (report kind) and `message` say why
      kRestart,  ///< the plant restarted its run: restart the history
    };
    Kind kind = Kind::kSample;
    int64_t index = -1;             ///< kSample: k
    State state{};                  ///< kSample: state k
    Command command{};              ///< the command state k + 1 answers
    std::optional<Beat> beat;       ///< beat state k
    std::optional<Beat> next_beat;  ///< beat state k + 1
    int64_t lost = 0;               ///< kGap
    std::string what;               ///< kGap: "gap in states", "missing command", …
    std::string message;            ///< kGap
  };

  explicit SamplePairer(PairingNeeds needs) : needs_(needs) {}

  const PairingNeeds& needs() const { return needs_; }

  /// @throws std::invalid_argument for a bad seq (see above); nothing changes then.
  std::vector<Event> OnState(const State& msg) {
    std::vector<Event> events;
    const int64_t newest = NewestState();
    const bool fresh = msg.seq == 0 && msg.command_seq < 0;
    const RunVerdict verdict = run_.Next(msg.seq, fresh, "state");
    switch (verdict.kind) {
      case RunVerdict::Kind::kRefused:
        throw std::invalid_argument(verdict.why);
      case RunVerdict::Kind::kCandidate:
        candidate_ = msg;  // only a suspicion so far
        candidate_commands_.clear();
        return events;
      case RunVerdict::Kind::kRestart:
        Restart(&events);
        if (verdict.from_candidate) {  // the plant confirms it
          pending_.push_back(*candidate_);
          if (!fresh) pending_.push_back(msg);
        } else {
          pending_.push_back(msg);
        }
        candidate_.reset();
        Process(&events);
        return events;
      case RunVerdict::Kind::kNext:
        if (verdict.dropped_candidate) {
          // The old run goes on: the state 0 was stale or forged, and the commands kept aside
          // meanwhile belong to the old run.
          for (const auto& [seq, c] : candidate_commands_) commands_.emplace(seq, c);
          candidate_.reset();
          candidate_commands_.clear();
        }
        pending_.push_back(msg);
        Process(&events);
        return events;
      case RunVerdict::Kind::kOlder:
        break;
    }
    if (msg.seq < newest - kResendReach)
      throw std::invalid_argument("stale state seq " + std::to_string(msg.seq) + " (newest " +
                                  std::to_string(newest) + ")");
    // A resend (held or used already: ignored), or the state a hole waits for.
    if (previous_ && msg.seq <= previous_->seq) return events;
    const auto at = std::lower_bound(pending_.begin(), pending_.end(), msg.seq,
                                     [](const State& held, int64_t seq) { return held.seq < seq; });
    if (at != pending_.end() && at->seq == msg.seq) return events;
    pending_.insert(at, msg);
    Process(&events);
    return events;
  }

  /// @throws std::invalid_argument for a bad seq or a conflicting second command.
  std::vector<Event> OnCommand(const Command& msg) {
    std::vector<Event> events;
    if (candidate_) {
      // Whose it is shows when the restart is confirmed or dropped; the first of a seq wins.
      if (candidate_commands_.size() < kMaxCommands) candidate_commands_.emplace(msg.seq, msg);
      return events;
    }
    const int64_t newest = commands_.empty() ? -1 : commands_.rbegin()->first;
    Guard(&command_leaps_, "command", msg.seq, newest);
    // A generator that restarted counts from 0 again: forget the old run's commands.
    if (!commands_.empty() && msg.seq + static_cast<int64_t>(kMaxCommands) < newest)
      commands_.clear();
    // The first command of a seq wins: a resend carries the same values, and a later message
    // reusing the seq (a stale or forged one) must not change a sample after the fact.
    const auto [it, added] = commands_.emplace(msg.seq, msg);
    if (!added) {
      if (msg.source == it->second.source) return events;  // a lockstep resend
      throw std::invalid_argument("a second command with seq " + std::to_string(msg.seq) +
                                  " from '" + msg.source + "'");
    }
    while (commands_.size() > kMaxCommands) commands_.erase(commands_.begin());
    Process(&events);
    return events;
  }

  /// @throws std::invalid_argument for a bad seq (see above); nothing changes then.
  std::vector<Event> OnBeat(const Beat& msg) {
    std::vector<Event> events;
    Guard(&beat_leaps_, "beat state", msg.seq, newest_beat_);
    if (newest_beat_ >= 0 && msg.seq <= newest_beat_) {
      if (msg.seq == 0 && msg.command_seq < 0 && newest_beat_ > 0) {
        beats_.clear();  // the plant restarted: its state 0 follows (or came first)
      } else if (msg.seq < newest_beat_ - kResendReach) {
        throw std::invalid_argument("stale beat state seq " + std::to_string(msg.seq) +
                                    " (newest " + std::to_string(newest_beat_) + ")");
      } else {
        // A resend beside the state's (held or used already: ignored), or one a hole waits for.
        if (beats_.count(msg.seq) > 0 || (previous_ && msg.seq < previous_->seq)) return events;
        beats_.emplace(msg.seq, msg);
        Process(&events);
        return events;
      }
    }
    newest_beat_ = msg.seq;
    beats_[msg.seq] = msg;
    while (beats_.size() > kMaxBeats) beats_.erase(beats_.begin());
    Process(&events);
    return events;
  }

  /// No message will come any more (the end of a recorded log): every waiting sample is now
  /// complete or lost, instead of waiting for messages that would have completed it.
  std::vector<Event> Finish() {
    std::vector<Event> events;
    finished_ = true;
    Process(&events);
    finished_ = false;
    return events;
  }

  /// The newest state held with everything the samples up to it need from the messages
  /// published up to it: every earlier sample is complete (or lost), and its own beat state is in
  /// hand when beat averages are needed. -1 before any. This is what a lockstep receipt (ack_t)
  /// acknowledges: the generator's next command can only bring what comes after it.
  int64_t newest_held_state() const {
    if (!previous_) return -1;
    const int64_t s = previous_->seq;
    if (needs_.beat && !FindBeat(s, previous_->command_seq)) return s - 1;
    return s;
  }

  /// States after the newest handled one, waiting for a message their sample needs (the newest
  /// handled state itself waits for its successor and is not counted).
  std::size_t pending_states() const { return pending_.size(); }

 private:
  // Throws std::invalid_argument for a seq the guard rejects or holds back.
  static void Guard(LeapGuard* guard, const std::string& what, int64_t seq, int64_t newest) {
    const std::string problem = guard->Problem(what, seq, newest);
    if (!problem.empty()) throw std::invalid_argument(problem);
  }

  // Forgets the old run: the new one starts from the candidate's
  // commands, and from a fresh beat state 0 if one came first.
  void Restart(std::vector<Event>* events) {
    previous_.reset();
    pending_.clear();
    commands_ = std::move(candidate_commands_);
    candidate_commands_.clear();
    const auto fresh = beats_.find(0);
    const bool keep = fresh != beats_.end() && fresh->second.command_seq < 0 &&
                      beats_.size() == 1 && newest_beat_ == 0;
    if (!keep) {
      beats_.clear();
      newest_beat_ = -1;
    }
    Event e;
    e.kind = Event::Kind::kRestart;
    events->push_back(std::move(e));
  }

  int64_t NewestState() const {
    return !pending_.empty() ? pending_.back().seq : previous_ ? previous_->seq : -1;
  }

  // The state that completes the previous one's sample has been handled: it becomes previous,
  // and beat states before it can no longer be used.
  void Advance() {
    previous_ = pending_.front();
    pending_.pop_front();
    beats_.erase(beats_.begin(), beats_.lower_bound(previous_->seq));
  }

  static Event Gap(int64_t lost, std::string what, std::string message) {
    Event e;
    e.kind = Event::Kind::kGap;
    e.lost = lost;
    e.what = std::move(what);
    e.message = std::move(message);
    return e;
  }

  // A beat state for sample seq `seq` answering `command_seq`, or nullopt.
  std::optional<Beat> FindBeat(int64_t seq, int64_t command_seq) const {
    const auto it = beats_.find(seq);
    if (it == beats_.end() || it->second.command_seq != command_seq) return std::nullopt;
    return it->second;
  }

  void Process(std::vector<Event>* events) {
    while (!pending_.empty()) {
      const State& s = pending_.front();
      if (!previous_ || s.seq != previous_->seq + 1) {
        if (previous_ && s.seq > previous_->seq + 1) {
          // The missing state may still come (a resend), unless too many wait behind it.
          if (pending_.size() < kMaxStatesAfterHole && !finished_) return;
          events->push_back(Gap(s.seq - previous_->seq - 1, "gap in states",
                                "missing state seq " + std::to_string(previous_->seq + 1) + " … " +
                                    std::to_string(s.seq - 1)));
        }
        Advance();
        continue;
      }
      const int64_t k = previous_->seq;
      Event e;
      e.kind = Event::Kind::kSample;
      e.index = k;
      std::string what, why;
      const auto cmd = commands_.find(s.command_seq);
      if (cmd != commands_.end()) {
        e.command = cmd->second;
      } else {
        what = "missing command";
        why = "no command seq " + std::to_string(s.command_seq) + " for state seq " +
              std::to_string(s.seq);
      }
      if (what.empty() && needs_.beat) {
        e.beat = FindBeat(k, previous_->command_seq);
        if (!e.beat) {
          what = "missing beat state";
          why = "no beat state seq " + std::to_string(k) + " answering command seq " +
                std::to_string(previous_->command_seq);
        }
      }
      if (what.empty() && needs_.next_beat) {
        e.next_beat = FindBeat(s.seq, s.command_seq);
        if (!e.next_beat) {
          what = "missing beat state";
          why = "no beat state seq " + std::to_string(s.seq) + " answering command seq " +
                std::to_string(s.command_seq);
        }
      }
      if (!what.empty()) {
        if (pending_.size() < kMaxPendingStates && !finished_) return;  // it may still come
        events->push_back(Gap(1, what, why + " (sample " + std::to_string(k) + " lost)"));
        Advance();
        continue;
      }
      e.state = *previous_;
      events->push_back(std::move(e));
      Advance();
    }
  }

  PairingNeeds needs_;
  RunStart run_{kPairedStates};  // where the states' run begins again
  LeapGuard command_leaps_, beat_leaps_;
  std::map<int64_t, Command> commands_;  // by seq, bounded
  std::optional<State> candidate_;       // a fresh state 0 mid-run, until confirmed or dropped
  std::map<int64_t, Command> candidate_commands_;  // commands since the candidate
  std::map<int64_t, Beat> beats_;                  // by seq, from the oldest still usable on
  int64_t newest_beat_ = -1;
  std::optional<State> previous_;
  std::deque<State> pending_;  // waiting for the next state or a message their sample needs
  bool finished_ = false;      // inside Finish(): nothing waits
};

}  // namespace odonata::pipeline

#pragma once
// A lockstep sender's patience with consumers landing a scheduled refit — one rule for
// odonata-signal's sequencer (pipeline/lockstep_sequencer.hpp) and odonata-replay. A consumer
// that says so on its heartbeat ("refitting") acknowledges nothing until it has landed: a timeout
// while only such consumers lack the awaited message resends nothing (a process that is not
// reading is helped by none) and costs no resend, for at most `max_timeouts` in a row, so a forged
// or stuck "refitting" cannot hold the run for ever (docs/lcm.md §10). Not thread-safe.

#include <cstdint>
#include <set>
#include <string>
#include <vector>

namespace odonata::pipeline {

class RefitPatience {
 public:
  enum class Verdict {
    kNotBusy,  ///< some consumer lacking it is not refitting (or none lacks it): the caller's rules
    kWait,     ///< only refitting consumers lack it: wait on, nothing resent (counted)
    kSpent,    ///< … but they have been refitting for max_timeouts() in a row: give up
  };

  explicit RefitPatience(int max_timeouts) : max_timeouts_(max_timeouts) {}

  /// `instance` says it is landing a refit (or no longer is).
  void SetBusy(const std::string& instance, bool busy) {
    if (busy)
      busy_.insert(instance);
    else
      busy_.erase(instance);
  }
  /// A consumer that left: nothing of it is remembered.
  void Forget(const std::string& instance) { busy_.erase(instance); }
  bool busy(const std::string& instance) const { return busy_.count(instance) > 0; }

  /// A timeout, while `laggards` lack the awaited message.
  Verdict OnTimeout(const std::vector<std::string>& laggards) {
    bool all_busy = !laggards.empty();
    for (const auto& c : laggards) all_busy = all_busy && busy(c);
    if (!all_busy) {
      in_a_row_ = 0;
      return Verdict::kNotBusy;
    }
    if (in_a_row_ >= max_timeouts_) return Verdict::kSpent;
    ++in_a_row_;
    ++total_;
    return Verdict::kWait;
  }
  /// The awaited message came, or a timeout was not theirs: the next wait starts a new row.
  void Reset() { in_a_row_ = 0; }

  int in_a_row() const { return in_a_row_; }
  int64_t total() const { return total_; }
  int max_timeouts() const { return max_timeouts_; }
  void set_max_timeouts(int n) { max_timeouts_ = n; }

 private:
  std::set<std::string> busy_;
  int max_timeouts_;
  int in_a_row_ = 0;
  int64_t total_ = 0;
};

}  // namespace odonata::pipeline

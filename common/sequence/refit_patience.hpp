#pragma once
// A lockstep sender's patience with consumers landing a scheduled refit — one rule for
// odonata-signal's sequencer (pipeline/lockstep_sequencer.hpp) and odonata-replay. A consumer
// that says so on its heartbeat ("refitting") acknowledges nothing until it has landed: a timeout
// while only such consumers lack the awaited message resends nothing (a process that is not
// reading is helped by none) and costs no resend, for at most `max_timeouts` in a row, so a forged
// or stuck "refitting" cannot hold the run for ever (docs/lcm.md §10). Not thread-safe.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

namespace odonata::pipeline {

/// How long a lockstep sender (odonata-signal --refit-wait, odonata-replay --refit-wait) waits, by
/// default, for consumers that say they are landing a scheduled refit before it gives up: ten
/// minutes on a signed bus, under one on a keyless one, where a forged "refitting" cannot be told
/// from a real one (docs/lcm.md §10).
inline constexpr double kSignedRefitWaitSeconds = 600;
inline constexpr double kKeylessRefitWaitSeconds = 45;

/// The patience of `refit_wait_s` seconds (< 0: the default for a bus with or without a key) in
/// timeouts of `timeout_ms` each.
inline int RefitWaitTimeouts(double refit_wait_s, bool keyed, int timeout_ms) {
  const double wait_s = refit_wait_s >= 0 ? refit_wait_s
                        : keyed           ? kSignedRefitWaitSeconds
                                          : kKeylessRefitWaitSeconds;
  return static_cast<int>(std::min(1e9, std::ceil(wait_s * 1000.0 / std::max(1, timeout_ms))));
}

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

  /// What a sender says every 5 s of a wait (a refit may take long; a forged or stuck
  /// "refitting" must not look like a hang), "" between: "waiting 10 s for id, landing …".
  std::string Notice(int timeout_ms, const std::string& waited_for, bool keyed) const {
    const int every = std::max(1, 5000 / std::max(1, timeout_ms));
    if (in_a_row_ == 0 || in_a_row_ % every != 0) return "";
    char line[512];
    std::snprintf(line, sizeof line,
                  "waiting %.0f s for %s, landing a scheduled refit (gives up after %.0f s%s)",
                  in_a_row_ * timeout_ms / 1000.0, waited_for.c_str(),
                  max_timeouts_ * timeout_ms / 1000.0,
                  keyed ? ""
                        : "; without a key a forged \"refitting\" looks the same: --refit-wait "
                          "for longer");
    return line;
  }

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

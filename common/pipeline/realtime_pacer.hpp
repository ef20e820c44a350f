#pragma once
// Real-time pacing without transport, beside the lockstep sequencer (lockstep_sequencer.hpp):
// when each message of a paced run is due. Sample k goes out at its own time from the start
// (t_k / speed), never at the previous send plus a period, so the pace does not drift with the
// loop's latency or a late wake-up (odonata-signal --mode realtime, odonata-replay paced).

#include <chrono>
#include <cstdint>

namespace odonata::pipeline {

class RealtimePacer {
 public:
  using Clock = std::chrono::steady_clock;

  RealtimePacer() = default;
  /// A run that starts at `start`, its own time running `speed` times faster than the clock.
  explicit RealtimePacer(Clock::time_point start, double speed = 1.0)
      : start_(start), speed_(speed) {}

  Clock::time_point start() const { return start_; }

  /// When the message at `t_s` seconds of the run's own time is due.
  Clock::time_point DueAt(double t_s) const {
    return start_ +
           std::chrono::round<Clock::duration>(std::chrono::duration<double>(t_s / speed_));
  }

  /// When sample k of a run at `rate_hz` is due.
  Clock::time_point DueAtSample(int64_t k, double rate_hz) const {
    return DueAt(static_cast<double>(k) / rate_hz);
  }

  /// How long from `now` until `due`: zero when it is late (sent at once, the next still due at
  /// its own time).
  static Clock::duration Wait(Clock::time_point due, Clock::time_point now) {
    return due > now ? due - now : Clock::duration::zero();
  }

 private:
  Clock::time_point start_{};
  double speed_ = 1.0;
};

}  // namespace odonata::pipeline

#pragma once
// Wing-beat averages from the per-step history: each wing's body-frame force over that wing's
// beat, and the body's motion and total force over the vehicle's mean beat.

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

#include "plant/wing_command.hpp"

namespace odonata::plant {

/// Fixed-capacity ring of per-step values of fixed length step_s, from which trailing windows
/// are read: the newest whole steps, plus the fraction of the step before them that completes
/// the window. The one ring both averagers below keep.
template <class Entry>
class TrailingStepRing {
 public:
  /// @pre step_s > 0, max_window_s ≥ step_s.
  TrailingStepRing(double step_s, double max_window_s, const Entry& zero)
      : step_s_(step_s),
        max_window_s_(max_window_s),
        ring_(static_cast<std::size_t>(std::ceil(max_window_s / step_s)) + 2, zero) {}

  void Clear() {
    next_ = 0;
    count_ = 0;
  }
  void Push(const Entry& entry) {
    ring_[next_] = entry;
    next_ = (next_ + 1) % ring_.size();
    if (count_ < ring_.size()) ++count_;
  }

  /// Calls visit(entry, weight) for the entries of the newest window_s seconds (clamped to
  /// [step_s, max_window_s]), newest first, the oldest one weighted by its fraction of a step,
  /// and returns the total weight (in steps). With a shorter history the window is the whole
  /// history; with none it is 0 and visit is never called.
  template <class Visit>
  double ForWindow(double window_s, Visit&& visit) const {
    if (count_ == 0) return 0.0;
    const double clamped_s = window_s < step_s_         ? step_s_
                             : window_s > max_window_s_ ? max_window_s_
                                                        : window_s;
    const double steps = clamped_s / step_s_;
    std::size_t full = static_cast<std::size_t>(steps);
    double fraction = steps - static_cast<double>(full);
    if (full >= count_) {
      full = count_;
      fraction = 0.0;
    }
    std::size_t idx = next_;
    for (std::size_t k = 0; k < full; ++k) {
      idx = (idx + ring_.size() - 1) % ring_.size();
      visit(ring_[idx], 1.0);
    }
    if (fraction > 0.0) {
      idx = (idx + ring_.size() - 1) % ring_.size();
      visit(ring_[idx], fraction);
    }
    return static_cast<double>(full) + fraction;
  }

  double step_s() const { return step_s_; }
  double max_window_s() const { return max_window_s_; }
  bool empty() const { return count_ == 0; }

 private:
  double step_s_{};
  double max_window_s_{};
  std::vector<Entry> ring_;  // fixed capacity, allocated once
  std::size_t next_{0};      // slot the next Push writes
  std::size_t count_{0};
};

/// Per-wing force components kept for averaging: column 0 = F_x, column 1 = F_z (body frame, N).
using WingForceXz = Eigen::Matrix<double, kWingCount, 2>;

/// Ring buffer of per-step mean forces (one entry per integration step of fixed length), from
/// which the mean over the last wing beat of each wing is read. A beat is 1/f of that wing's
/// current frequency, capped at max_window_s (a stopped wing has no beat).
class WingBeatAverager {
 public:
  /// @pre step_s > 0, max_window_s ≥ step_s.
  WingBeatAverager(double step_s, double max_window_s);

  /// Forgets the history.
  void Clear() { ring_.Clear(); }
  /// Appends the mean force of each wing over one integration step.
  void Push(const WingForceXz& step_mean_force_n) { ring_.Push(step_mean_force_n); }
  /// Mean over the most recent window_s[w] seconds for each wing w (a fractional oldest step is
  /// weighted by the fraction). With a shorter history the mean is over the whole history; with
  /// no history it is zero.
  WingForceXz Average(const Eigen::Matrix<double, kWingCount, 1>& window_s) const;

  double max_window_s() const { return ring_.max_window_s(); }
  bool empty() const { return ring_.empty(); }

 private:
  TrailingStepRing<WingForceXz> ring_;
};

/// The body signals averaged over a beat, in this order in a BeatVector.
enum BeatSignal : int {
  kBeatVx = 0,     ///< V_b x (m/s)
  kBeatVy = 1,     ///< V_b y (m/s)
  kBeatVz = 2,     ///< V_b z (m/s)
  kBeatP = 3,      ///< ω_b x (rad/s)
  kBeatQ = 4,      ///< ω_b y (rad/s)
  kBeatR = 5,      ///< ω_b z (rad/s)
  kBeatRoll = 6,   ///< roll (rad), continuous (unwrapped) so a mean across ±π is meaningful
  kBeatPitch = 7,  ///< pitch (rad)
  kBeatYaw = 8,    ///< yaw (rad), continuous (unwrapped)
  kBeatFx = 9,     ///< total force of the four wings along body x (N)
  kBeatFz = 10,    ///< total force of the four wings along body z (N)
  kBeatSignalCount = 11,
};
using BeatVector = Eigen::Matrix<double, kBeatSignalCount, 1>;

/// Ring buffer of per-step body signals, from which their trailing mean over one window (the
/// vehicle's last wing beat) is read. Push is O(1); Average is O(window / step).
class BeatSignalAverager {
 public:
  /// @pre step_s > 0, max_window_s ≥ step_s.
  BeatSignalAverager(double step_s, double max_window_s);

  void Clear() { ring_.Clear(); }
  /// Appends one step's value of every signal (the state at the end of the step; the forces as
  /// their mean over the step). Angles must be continuous from one push to the next.
  void Push(const BeatVector& step_value) { ring_.Push(step_value); }
  /// Mean over the most recent window_s seconds (clamped to [step, max_window_s]); zero with no
  /// history.
  BeatVector Average(double window_s) const;

  double max_window_s() const { return ring_.max_window_s(); }
  bool empty() const { return ring_.empty(); }

 private:
  TrailingStepRing<BeatVector> ring_;
};

}  // namespace odonata::plant

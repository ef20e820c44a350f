#pragma once
// Wing-beat averages of each wing's body-frame force from the per-step history.

#include <Eigen/Core>
#include <vector>

#include "plant/wing_command.hpp"

namespace odonata::plant {

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
  void Clear();
  /// Appends the mean force of each wing over one integration step.
  void Push(const WingForceXz& step_mean_force_n);
  /// Mean over the most recent window_s[w] seconds for each wing w (a fractional oldest step is
  /// weighted by the fraction). With a shorter history the mean is over the whole history; with
  /// no history it is zero.
  WingForceXz Average(const Eigen::Matrix<double, kWingCount, 1>& window_s) const;

  double max_window_s() const { return max_window_s_; }
  bool empty() const { return count_ == 0; }

 private:
  double step_s_{};
  double max_window_s_{};
  std::vector<WingForceXz> ring_;  // fixed capacity, allocated once
  std::size_t next_{0};            // slot the next Push writes
  std::size_t count_{0};
};

}  // namespace odonata::plant

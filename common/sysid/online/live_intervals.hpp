#pragma once
// The online identifier's prediction intervals (issue 60 point 1, the live side; docs/identifier.md
// §7.6): per output, one step ahead, K steps ahead and in free run, ŷ ± h with h the conformal
// half width (metrics/conformal.hpp) of the model's own residuals on the newest kWindow samples it
// learned. Each residual is taken before its target was learned — ŷ(k | k−1) and ŷ(k | k−K) are
// made before y(k) is — so none is in-sample, as odonata-fit's calibration rows are not. A sample's
// interval uses only residuals of earlier samples. A frozen model keeps the widths of the flight
// it learned on, as odonata-fit keeps its calibration's; a model from elsewhere (a RESET, a
// snapshot) starts with none, and a landed refit's model with its own calibration residuals (the
// chosen candidate on the selection's hold-out: odonata-fit's). What it does not promise: a
// flight unlike the one learned (another regime, another vehicle).

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include <Eigen/Core>

namespace odonata::sysid {

/// Residuals y − ŷ (targets × outputs) to start a window from: a landed refit's chosen candidate
/// on the hold-out it was judged on, as odonata-fit calibrates its intervals (RefitOutcome).
/// One step ahead; K steps ahead with `horizon` K (empty without); in free run (empty without
/// output lags).
struct SeedResiduals {
  Eigen::MatrixXd one_step, ahead, free_run;
  int horizon = 0;
};

class LiveIntervals {
 public:
  static constexpr std::size_t kWindow = 2000;  ///< residuals kept per output and mode (20 s)
  /// The widths are recomputed every this many samples added (their cost, not their meaning).
  static constexpr int64_t kRecomputeEvery = 10;

  /// @throws std::invalid_argument for a level outside (0, 1).
  explicit LiveIntervals(double level = 0.9);

  /// A learned sample's measured outputs and the predictions made before it was learned: one
  /// step ahead, with a horizon K steps ahead (`ahead` empty without), and the model's free run
  /// (`free_run` empty without). Non-finite residuals are left out.
  void Add(const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted,
           const Eigen::VectorXd& ahead, const Eigen::VectorXd& free_run = {});
  /// Per output, the half width now (+∞ while too few residuals for the level). Sized as the
  /// outputs of the last Add (empty before any).
  const Eigen::VectorXd& one_step() const { return one_step_width_; }
  const Eigen::VectorXd& ahead() const { return ahead_width_; }
  const Eigen::VectorXd& free_run() const { return free_run_width_; }
  double level() const { return level_; }
  void Clear();
  /// Forgets the window and starts it from `seed` (its newest kWindow rows): a new model is as
  /// sure as its calibration says, not unknown, and the older models' residuals leave at once.
  /// The K-step residuals only when their horizon is `horizon`, the one the reports carry.
  void Seed(const SeedResiduals& seed, int horizon);

 private:
  void Recompute();
  double level_;
  std::vector<std::deque<double>> one_step_, ahead_,
      free_run_;  // |residual| per output, newest last
  Eigen::VectorXd one_step_width_, ahead_width_, free_run_width_;
  int64_t added_ = 0;
};

}  // namespace odonata::sysid

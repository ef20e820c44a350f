#pragma once
// Tracking between scheduled refits (docs/identifier.md §6.3): recursive *global* least squares
// on every rule's consequents at once, with the premises the refit chose, continued from the
// refit. Its prior is the refit's consequents θ₀ with covariance P₀ = (ΦᵀΦ + δI)⁻¹ over the
// samples the refit learned from, so a sample moves the model as one more row of the refit's
// own least-squares problem would, not as independent per-rule learners pulling a jointly
// fitted model apart.

#include <vector>

#include <Eigen/Core>

#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

class ConsequentTracker {
 public:
  /// P₀ per output from the regressors of `samples` (raw units, the model's scaling), with the
  /// relative ridge δ = `ridge` × mean(diag ΦᵀΦ). Too few rows for the lags: an empty tracker.
  static ConsequentTracker Build(const NarxModel& model, const Series& samples,
                                 double ridge = 1e-6);
  /// The same from the samples' regression rows (BuildRegression), when the caller has them.
  static ConsequentTracker Build(const NarxModel& model, const RegressionData& rows,
                                 double ridge = 1e-6);

  /// One RLS step of every output's consequents on raw regressor x and measured y, with each
  /// output's forgetting factor λ. Does nothing when empty, when the model's rule counts are not
  /// the ones it was built for, or on non-finite values.
  void Step(NarxModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& y);

  bool empty() const { return covariance_.empty(); }
  long steps() const { return steps_; }
  /// The rows of Φ for output `o` at the scaled regressor: [φ₁z, …, φ_Rz] (rule-major).
  static Eigen::VectorXd GlobalRow(const fuzzy::FuzzyModel& m,
                                   const Eigen::Ref<const Eigen::VectorXd>& x_scaled);

 private:
  std::vector<Eigen::MatrixXd> covariance_;  // per output, m × m
  std::vector<int> rules_;                   // per output, the rule count P is sized for
  long steps_ = 0;
};

}  // namespace odonata::sysid

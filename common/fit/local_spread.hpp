#pragma once
// Where a prediction interval widens (issue 60 point 1, "local where the data says so";
// docs/identifier.md §7.6): a scale σ̂(x) per output, larger in the regimes whose rules fitted
// their rows loosely or stood for few of them.
//
// From a model and the rows it trained on, per output: the squared one-step residuals e_k² are
// modelled on the same rules, a singleton per rule fitted by least squares on the normalised
// firings w_kj (c = argmin Σ_k (e_k² − Σ_j w_kj c_j)², then clamped at 0) — unblended where the
// firings overlap, as a weighted mean per rule is not — and at a regressor x
//   σ̂²(x) = Σ_j w_j(x) c_j (1 + p / n_j) + kFloorShare · s̄² + s̄² · max(0, d / d₉₅ − 1)
// with n_j = Σ_k w_kj the rows rule j stood for and p its consequent's parameters (1 + p/n_j, the
// mean leverage of a least-squares prediction on n_j rows: a rule that saw little is wider; below
// one row, s̄² (1 + p)); c_j is held within the largest squared residual; s̄² the output's mean
// squared residual, a floor so that a rule which fitted its rows exactly promises no zero width; d
// the squared weighted distance of x to its nearest rule, Σ_i (x_i − c_i)² / σ_i², and d₉₅ the
// one 95 % of the training rows lie within: beyond it the rules know nothing of the error, whose
// variance grows by s̄² per d₉₅ (its spread with the distance itself, as a linear model's
// extrapolation error does). Conformal intervals normalised by σ̂ (prediction_intervals.hpp) keep
// their coverage guarantee for any σ̂; σ̂ only decides where the width goes.

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "sysid/model/narx_model.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit {

/// Of the output's mean squared residual, the variance every σ̂² keeps (a tenth: set a priori).
inline constexpr double kFloorShare = 0.1;
/// The share of training rows within d₉₅ of their nearest rule (set a priori).
inline constexpr double kReachQuantile = 0.95;

class LocalSpread {
 public:
  /// σ̂ = 1 everywhere: one width per output and mode.
  LocalSpread() = default;
  /// The rules' spreads of `model` on `train`, the series it was trained on.
  /// @throws std::invalid_argument when the series has no complete regressor.
  static LocalSpread Fit(const sysid::NarxModel& model, const sysid::Series& train);

  /// σ̂ per output at each target of `series` (targets × outputs, BuildRegression's rows), raw
  /// output units; 1 where the spread is not fitted or the fitted model's residuals were all 0.
  Eigen::MatrixXd At(const sysid::RegressorSpec& spec, const sysid::Series& series) const;
  bool fitted() const { return model_ != nullptr; }

 private:
  std::shared_ptr<const sysid::NarxModel> model_;
  std::vector<Eigen::VectorXd> rule_variance_;  // c_j (1 + p / n_j) per output
  Eigen::VectorXd floor_;                       // kFloorShare · s̄² per output
  Eigen::VectorXd reach_;                       // d₉₅ per output
};

}  // namespace odonata::fit

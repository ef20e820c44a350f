#pragma once
// How sure each rule's local linear model is (issue 60 point 2; docs/identifier.md §7.4): the
// covariance of its raw parameters [c; a_1 … a_n, b …] and, by the delta method, the standard
// errors of what the readable form prints — each pole's time constant and each input's gain.
//
// A rule's local model is read as a weighted least-squares estimate on the training rows, each
// row weighted by the rule's normalised firing w_k there (the weights its consequent is fitted
// with; docs/identifier.md §6). With φ_k = [1, x_k] the raw regressor and e_k = y_k − ŷ_k the
// model's one-step residual:
//   A = Σ w_k φ_k φ_kᵀ,   C = Σ w_k² φ_k φ_kᵀ,   σ² = Σ w_k e_k² / (Σ w_k − p),
//   Cov(θ) = σ² A⁻¹ C A⁻¹                                  (p = parameters of the rule)
// With one rule (w = 1) this is ordinary least squares' σ² (ΦᵀΦ)⁻¹, exact for an ARX plant with
// white equation noise. What it does not cover: the parameters' shift by the simulation-error
// stages (an output-error fit), the premises' own uncertainty, and a flight unlike the training
// one. Standard errors of a function f(θ) (a time constant, a gain): √(∇fᵀ Cov ∇f), ∇f by
// central differences of kDeltaStep relative size.

#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include "sysid/model/narx_model.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

/// Relative step of the central differences (of max(|θ_i|, 1e-3)).
inline constexpr double kDeltaStep = 1e-6;

struct LocalUncertainty {
  /// Of [constant; coefficients] in raw units (RawLinearModel's order); empty when the rule has
  /// fewer effective rows than parameters (then every standard error below is NaN).
  Eigen::MatrixXd covariance;
  double effective_rows = 0.0;  ///< Σ w_k: the rows the rule stands for
  double residual_std = 0.0;    ///< σ, raw output units
  /// Per pole, in LocalDynamics::time_constants' order: the standard error (s, or samples).
  std::vector<double> time_constant_se;
  /// Per input signal, in LocalDynamics::dc_gain's order: the standard error of the gain.
  std::vector<std::pair<std::string, double>> dc_gain_se;
};

/// Every rule of `output`, in order, from the training series the model was fitted on.
/// Linear consequents only (a singleton rule has no dynamics): empty otherwise.
std::vector<LocalUncertainty> LocalModelUncertainty(const NarxModel& model, int output,
                                                    const Series& train, double sample_time_s);

/// {"effective_rows", "residual_std", "time_constants_se_s" (or "_samples"), "dc_gain_se":
/// {input: se}, "parameter_covariance": [[…]…]} (NaN as null).
nlohmann::json ToJson(const LocalUncertainty& u, double sample_time_s);

/// Every output's rules' parameter covariances, as a model file keeps them beside the model
/// (NarxModel::Save): {output: [per rule, the raw [constant; coefficients] covariance as rows, or
/// null where the rule stands for fewer rows than parameters]}; null without linear consequents.
nlohmann::json LocalCovariancesToJson(const NarxModel& model, const Series& train,
                                      double sample_time_s);

/// "τ 0.42 ± 0.03 s, gain 31 ± 2 from m2": the slowest pole's time constant and the gains with
/// their standard errors, as DescribeDynamics says them without.
std::string DescribeWithUncertainty(const RegressorSpec& spec, int output, const NarxModel& model,
                                    int rule, const LocalUncertainty& u, double sample_time_s);

}  // namespace odonata::sysid

#pragma once
// The recursive least-squares step: the one home of the global RLS that the live ARX
// (recursive_arx.hpp) and the consequent tracker between refits (consequent_tracker.hpp) take.
//
// The fuzzy model's own per-rule learning (fuzzy/linear_consequent.cpp) is another estimator,
// not a copy of this one: each rule's step is weighted by its normalised firing, its forgetting
// scaled by that weight and its covariance's trace capped (docs/identifier.md §3), in the
// learner's hot path on raw storage.

#include <Eigen/Core>

namespace odonata::sysid {

/// θ (parameters × outputs, one covariance P shared by the outputs) learns the row z with the
/// targets y, forgetting with λ:
///   d = λ + zᵀPz,  K = Pz / d,  θ += K (y − θᵀz)ᵀ,  P = (P − K (Pz)ᵀ) / λ,  symmetrised.
/// λ = 1 forgets nothing. Returns false, changing nothing, when d is not positive (a P that
/// lost its definiteness).
inline bool RecursiveLeastSquaresStep(Eigen::MatrixXd& theta, Eigen::MatrixXd& p,
                                      const Eigen::VectorXd& z, const Eigen::VectorXd& y,
                                      double lambda = 1.0) {
  const Eigen::VectorXd pz = p * z;
  const double denominator = lambda + z.dot(pz);
  if (!(denominator > 0.0)) return false;
  const Eigen::VectorXd gain = pz / denominator;
  const Eigen::VectorXd error = y - theta.transpose() * z;
  theta.noalias() += gain * error.transpose();
  p.noalias() -= gain * pz.transpose();
  if (lambda != 1.0) p /= lambda;
  // Rounding makes P drift from symmetric over a long record; keep it symmetric.
  p = 0.5 * (p + p.transpose()).eval();
  return true;
}

}  // namespace odonata::sysid

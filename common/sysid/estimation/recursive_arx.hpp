#pragma once
// The live linear baseline (docs/identifier.md §6.4): ARX on the fuzzy model's regressors,
// learned sample by sample by recursive least squares with one covariance shared by every
// output. With no forgetting it is the batch ArxModel on the samples seen so far (up to the
// prior), so the identifier can say live, as odonata-fit says offline, whether its fuzzy model
// beats linear.

#include <Eigen/Core>

#include "sysid/model/scaling.hpp"

namespace odonata::sysid {

class RecursiveArx {
 public:
  /// Regressors and outputs are scaled with `scaling` (the fuzzy model's at the start), so the
  /// prior P₀ = p0·I means the same for every experiment.
  /// @pre scaling.Problems() is empty; p0 > 0.
  explicit RecursiveArx(const Scaling& scaling, double p0 = 1e6);

  /// One RLS step on the raw regressor x and the measured y. Non-finite values change nothing.
  void Update(const Eigen::VectorXd& x, const Eigen::VectorXd& y);
  /// ŷ = θᵀ[1; x_scaled], in raw units.
  Eigen::VectorXd Predict(const Eigen::VectorXd& x) const;
  /// Back to the prior: no samples learned.
  void Reset();

  long samples() const { return samples_; }
  /// (N+1) × outputs in scaled units, the intercept first.
  const Eigen::MatrixXd& coefficients() const { return theta_; }

 private:
  Eigen::VectorXd Regressor(const Eigen::VectorXd& x) const;

  Scaling scaling_;
  double p0_;
  Eigen::MatrixXd theta_, p_;
  long samples_ = 0;
};

}  // namespace odonata::sysid

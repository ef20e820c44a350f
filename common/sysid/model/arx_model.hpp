#pragma once
// The linear baseline: ARX by least squares on the same regressors as the fuzzy model.

#include <Eigen/Core>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

/// y_o(t) = θ_o0 + θ_oᵀ x(t), one least-squares fit per output (with a tiny ridge so a
/// constant regressor does not make the problem singular).
class ArxModel {
 public:
  /// @throws std::invalid_argument if the series is too short for the lags.
  static ArxModel Fit(const RegressorSpec& spec, const Series& train);
  Eigen::VectorXd Predict(const Eigen::VectorXd& x) const;
  const Eigen::MatrixXd& coefficients() const { return theta_; }  ///< (N+1) × outputs

 private:
  Eigen::MatrixXd theta_;
};

}  // namespace odonata::sysid

#pragma once
// The second linear-in-parameters baseline: ARX with squared inputs. If a fuzzy model only beats
// ARX because the input enters squared (lift ∝ f²φ₀²), this baseline closes the gap; if it does
// not, the nonlinearity involves the state (docs/identifier.md §8).

#include <Eigen/Dense>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

/// y_o(t) = θ_o0 + θ_oᵀ [x(t); q(t)], where q(t) holds, for each input lag, every product
/// u_i·u_j (i ≤ j) of the inputs at that lag: squares and cross products, lag by lag (for
/// inputs f, φ₀ at one lag: f², fφ₀, φ₀²). Output lags enter linearly, as in ARX. Solved by a
/// column-pivoting QR with a tiny ridge, like ArxModel.
class QuadraticArxModel {
 public:
  /// @throws std::invalid_argument if the series is too short for the lags.
  static QuadraticArxModel Fit(const RegressorSpec& spec, const Series& train);
  /// @pre x has spec.size() entries.
  Eigen::VectorXd Predict(const Eigen::VectorXd& x) const;
  /// Regressors after the products are appended: spec.size() + lags · I(I+1)/2.
  Eigen::Index features() const { return theta_.rows() - 1; }

 private:
  Eigen::VectorXd Features(const Eigen::VectorXd& x) const;

  int first_input_ = 0;  // index in x of u_1's first lag
  int inputs_ = 0;
  int lags_ = 0;
  Eigen::MatrixXd theta_;  // (features + 1) × outputs
};

}  // namespace odonata::sysid

#pragma once
// Affine scaling kept inside the model (docs/identifier.md §7): regressors to [−1, 1], outputs
// standardised, so learning rates and widths mean the same for every experiment.

#include <string>

#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

namespace odonata::sysid {

struct Scaling {
  Eigen::VectorXd regressor_mid;   ///< (max + min) / 2 per regressor, raw units
  Eigen::VectorXd regressor_half;  ///< (max − min) / 2, or 1 for a constant regressor
  Eigen::VectorXd output_mean;     ///< per output, raw units
  Eigen::VectorXd output_std;      ///< per output, or 1 for a constant output

  /// Ranges from training data (regressors rows × N, targets rows × outputs).
  static Scaling FromData(const Eigen::Ref<const Eigen::MatrixXd>& x,
                          const Eigen::Ref<const Eigen::MatrixXd>& y);

  Eigen::VectorXd ScaleRegressor(const Eigen::Ref<const Eigen::VectorXd>& x) const {
    return ((x - regressor_mid).array() / regressor_half.array()).matrix();
  }
  double ScaleOutput(int o, double y) const { return (y - output_mean(o)) / output_std(o); }
  /// Every row of x (rows × regressors) and of y (rows × outputs) scaled as ScaleRegressor and
  /// ScaleOutput scale one, element for element the same arithmetic.
  Eigen::MatrixXd ScaleRegressorRows(const Eigen::Ref<const Eigen::MatrixXd>& x) const {
    return ((x.rowwise() - regressor_mid.transpose()).array().rowwise() /
            regressor_half.transpose().array())
        .matrix();
  }
  Eigen::MatrixXd ScaleOutputRows(const Eigen::Ref<const Eigen::MatrixXd>& y) const {
    return ((y.rowwise() - output_mean.transpose()).array().rowwise() /
            output_std.transpose().array())
        .matrix();
  }
  double UnscaleOutput(int o, double ys) const { return output_mean(o) + output_std(o) * ys; }

  /// Every problem (sizes that differ, a range or deviation that is not positive and finite,
  /// a centre that is not finite), empty when fine.
  std::string Problems() const;
  /// Problems() refuses centres and ranges beyond these magnitudes (finite but absurd ones).
  static constexpr double kMaxMagnitude = 1e200;
  static constexpr double kMinMagnitude = 1e-200;
  nlohmann::json ToJson() const;
  static Scaling FromJson(const nlohmann::json& j);
};

}  // namespace odonata::sysid

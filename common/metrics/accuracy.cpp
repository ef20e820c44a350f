#include "metrics/accuracy.hpp"

#include <cmath>
#include <limits>
#include "contract/precondition.hpp"

namespace odonata::metrics {

double FitPercent(double error_norm, double spread) {
  if (spread > 0.0) return 100.0 * (1.0 - error_norm / spread);
  return error_norm == 0.0 ? 100.0 : -std::numeric_limits<double>::infinity();
}

Accuracy Score(const Eigen::Ref<const Eigen::VectorXd>& measured,
               const Eigen::Ref<const Eigen::VectorXd>& predicted) {
  ODONATA_EXPECTS(measured.size() == predicted.size() && measured.size() > 0);
  const double n = static_cast<double>(measured.size());
  const Eigen::VectorXd err = measured - predicted;
  const double mean_y = measured.mean();
  const double spread = (measured.array() - mean_y).matrix().norm();
  const double err_norm = err.norm();
  const double mean_e = err.mean();
  const double var_y = spread * spread / n;
  const double var_e = (err.array() - mean_e).square().sum() / n;
  Accuracy a;
  a.samples = static_cast<long>(measured.size());
  a.rmse = err_norm / std::sqrt(n);
  const double inf = std::numeric_limits<double>::infinity();
  a.fit_percent = FitPercent(err_norm, spread);
  if (spread > 0.0) {
    a.vaf_percent = 100.0 * (1.0 - var_e / var_y);
    a.ndei = a.rmse / std::sqrt(var_y);
  } else {
    const bool exact = err_norm == 0.0;
    a.vaf_percent = exact ? 100.0 : -inf;
    a.ndei = exact ? 0.0 : inf;
  }
  return a;
}

}  // namespace odonata::metrics

#include "sysid/free_run.hpp"

#include <cmath>
#include <stdexcept>

namespace odonata::sysid {

Eigen::MatrixXd PredictOneStep(const RegressorSpec& spec, const Series& series,
                               const Predictor& predict) {
  const Eigen::Index t0 = spec.first_target();
  const Eigen::Index rows = series.samples() - t0;
  if (rows < 1) throw std::invalid_argument("too few samples for the lags");
  Eigen::MatrixXd out(rows, series.outputs.cols());
  Eigen::VectorXd x(spec.size());
  for (Eigen::Index r = 0; r < rows; ++r) {
    spec.Fill(t0 + r, series.outputs, series.inputs, x);
    out.row(r) = predict(x).transpose();
  }
  return out;
}

Eigen::MatrixXd SimulateFreeRun(const RegressorSpec& spec, const Series& series,
                                const Predictor& predict, bool* diverged) {
  const Eigen::Index t0 = spec.first_target();
  const Eigen::Index rows = series.samples() - t0;
  if (rows < 1) throw std::invalid_argument("too few samples for the lags");
  Eigen::MatrixXd simulated = series.outputs;  // rows < t0 stay measured (initial conditions)
  Eigen::VectorXd x(spec.size());
  bool bad = false;
  for (Eigen::Index t = t0; t < series.samples(); ++t) {
    spec.Fill(t, simulated, series.inputs, x);
    const Eigen::VectorXd y = predict(x);
    for (Eigen::Index o = 0; o < y.size(); ++o) {
      if (std::isfinite(y(o))) {
        simulated(t, o) = y(o);
      } else {
        simulated(t, o) = simulated(t - 1 >= 0 ? t - 1 : 0, o);
        bad = true;
      }
    }
  }
  if (diverged) *diverged = bad;
  return simulated.bottomRows(rows);
}

}  // namespace odonata::sysid

#include "sysid/model/free_run.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace odonata::sysid {

Eigen::MatrixXd PredictOneStep(const RegressorSpec& spec, const Series& series,
                               const Predictor& predict) {
  const auto targets = TargetRows(spec, series);
  if (targets.empty()) throw std::invalid_argument("too few samples for the lags");
  Eigen::MatrixXd out(static_cast<Eigen::Index>(targets.size()), series.outputs.cols());
  Eigen::VectorXd x(spec.size());
  for (std::size_t r = 0; r < targets.size(); ++r) {
    spec.Fill(targets[r], series.outputs, series.inputs, x);
    out.row(static_cast<Eigen::Index>(r)) = predict(x).transpose();
  }
  return out;
}

namespace {

// One step of a free run: predicts target row t from `simulated` (measured before the run, the
// run's own predictions within it) and writes the prediction there; a non-finite one is held at
// the last value, and `bad` says so.
void SimulateStep(const RegressorSpec& spec, Eigen::Index t, Eigen::MatrixXd& simulated,
                  const Eigen::MatrixXd& inputs, const Predictor& predict, Eigen::VectorXd& x,
                  bool& bad) {
  spec.Fill(t, simulated, inputs, x);
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

}  // namespace

Eigen::MatrixXd SimulateFreeRun(const RegressorSpec& spec, const Series& series,
                                const Predictor& predict, bool* diverged) {
  const auto targets = TargetRows(spec, series);
  if (targets.empty()) throw std::invalid_argument("too few samples for the lags");
  // Rows that are not targets (each segment's first ones) stay measured: the initial conditions
  // the simulation of that segment starts from.
  Eigen::MatrixXd simulated = series.outputs;
  Eigen::MatrixXd out(static_cast<Eigen::Index>(targets.size()), series.outputs.cols());
  Eigen::VectorXd x(spec.size());
  bool bad = false;
  for (std::size_t r = 0; r < targets.size(); ++r) {
    const Eigen::Index t = targets[r];
    SimulateStep(spec, t, simulated, series.inputs, predict, x, bad);
    out.row(static_cast<Eigen::Index>(r)) = simulated.row(t);
  }
  if (diverged) *diverged = bad;
  return out;
}

Eigen::MatrixXd PredictAhead(const RegressorSpec& spec, const Series& series,
                             const Predictor& predict, int horizon, bool* diverged, int stride) {
  if (horizon < 1) throw std::invalid_argument("the prediction horizon must be >= 1");
  if (stride < 1) throw std::invalid_argument("the stride must be >= 1");
  const auto targets = TargetRows(spec, series);
  if (targets.empty()) throw std::invalid_argument("too few samples for the lags");
  Eigen::MatrixXd simulated = series.outputs;
  Eigen::MatrixXd out(static_cast<Eigen::Index>(targets.size()), series.outputs.cols());
  Eigen::VectorXd x(spec.size());
  bool bad = false;
  out.setConstant(std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < targets.size(); ++r) {
    if ((targets.size() - 1 - r) % static_cast<std::size_t>(stride) != 0) continue;
    // The run of consecutive targets that ends at r, at most `horizon` long.
    std::size_t first = r;
    while (first > 0 && r - first + 1 < static_cast<std::size_t>(horizon) &&
           targets[first - 1] == targets[first] - 1)
      --first;
    for (std::size_t q = first; q <= r; ++q)
      SimulateStep(spec, targets[q], simulated, series.inputs, predict, x, bad);
    out.row(static_cast<Eigen::Index>(r)) = simulated.row(targets[r]);
    for (std::size_t q = first; q <= r; ++q)  // the next start reads measured outputs again
      simulated.row(targets[q]) = series.outputs.row(targets[q]);
  }
  if (diverged) *diverged = bad;
  return out;
}

std::map<std::string, Eigen::MatrixXd> ModePredictions(const RegressorSpec& spec,
                                                       const Series& series,
                                                       const Predictor& predict, int horizon) {
  std::map<std::string, Eigen::MatrixXd> modes;
  modes["one_step"] = PredictOneStep(spec, series, predict);
  if (spec.output_lags > 0) {
    bool diverged = false;
    modes["free_run"] = SimulateFreeRun(spec, series, predict, &diverged);
    if (horizon > 1) modes["k_step"] = PredictAhead(spec, series, predict, horizon, &diverged);
  }
  return modes;
}

}  // namespace odonata::sysid

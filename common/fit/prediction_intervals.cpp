#include "fit/prediction_intervals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics/conformal.hpp"

namespace odonata::fit {
namespace {

// The predictions of each mode odonata-fit scores, by name, and the targets.
std::map<std::string, Eigen::MatrixXd> ModePredictions(const sysid::RegressorSpec& spec,
                                                       const sysid::Series& s,
                                                       const sysid::Predictor& predict,
                                                       int horizon) {
  std::map<std::string, Eigen::MatrixXd> modes;
  modes["one_step"] = sysid::PredictOneStep(spec, s, predict);
  if (spec.output_lags > 0) {
    bool diverged = false;
    modes["free_run"] = sysid::SimulateFreeRun(spec, s, predict, &diverged);
    if (horizon > 1) modes["k_step"] = sysid::PredictAhead(spec, s, predict, horizon, &diverged);
  }
  return modes;
}

// The conformal half width of the finite residuals (metrics/conformal.hpp).
double ConformalHalfWidth(const Eigen::VectorXd& y, const Eigen::VectorXd& yhat, double level) {
  std::vector<double> e;
  e.reserve(static_cast<std::size_t>(y.size()));
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (std::isfinite(yhat(r)) && std::isfinite(y(r))) e.push_back(std::abs(y(r) - yhat(r)));
  return metrics::ConformalHalfWidth(e, level);
}

}  // namespace

IntervalWidths CalibrateIntervals(const sysid::RegressorSpec& spec,
                                  const sysid::Series& calibration, const sysid::Predictor& predict,
                                  int horizon, double level) {
  if (!(level > 0.0 && level < 1.0))
    throw std::invalid_argument("the interval's level must be in (0, 1), not " +
                                std::to_string(level));
  IntervalWidths w;
  w.level = level;
  const Eigen::MatrixXd y = sysid::Targets(spec, calibration);
  w.calibration_rows = y.rows();
  for (const auto& [mode, yhat] : ModePredictions(spec, calibration, predict, horizon)) {
    Eigen::VectorXd half(y.cols());
    for (Eigen::Index o = 0; o < y.cols(); ++o)
      half(o) = ConformalHalfWidth(y.col(o), yhat.col(o), level);
    w.half_width[mode] = half;
  }
  return w;
}

nlohmann::json IntervalScore(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& yhat, double half_width,
                             const IntervalWidths& widths) {
  metrics::IntervalTally tally;
  for (Eigen::Index r = 0; r < y.size(); ++r) tally.Add(y(r), yhat(r), half_width);
  nlohmann::json j = tally.ToJson();
  j.erase("samples");
  j["level"] = widths.level;
  j["calibration_rows"] = widths.calibration_rows;
  return j;
}

}  // namespace odonata::fit

#include "fit/prediction_intervals.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "metrics/conformal.hpp"

namespace odonata::fit {
namespace {

// The conformal half width of the finite residuals, each over its σ̂ (metrics/conformal.hpp).
double ConformalHalfWidth(const Eigen::VectorXd& y, const Eigen::VectorXd& yhat,
                          const Eigen::VectorXd& sigma, double level) {
  std::vector<double> e;
  e.reserve(static_cast<std::size_t>(y.size()));
  for (Eigen::Index r = 0; r < y.size(); ++r)
    if (std::isfinite(yhat(r)) && std::isfinite(y(r)))
      e.push_back(std::abs(y(r) - yhat(r)) / sigma(r));
  return metrics::ConformalHalfWidth(e, level);
}

}  // namespace

IntervalWidths CalibrateIntervals(const sysid::RegressorSpec& spec,
                                  const sysid::Series& calibration, const sysid::Predictor& predict,
                                  int horizon, double level, const LocalSpread& spread) {
  if (!(level > 0.0 && level < 1.0))
    throw std::invalid_argument("the interval's level must be in (0, 1), not " +
                                std::to_string(level));
  IntervalWidths w;
  w.level = level;
  w.spread = spread;
  const Eigen::MatrixXd y = sysid::Targets(spec, calibration);
  const Eigen::MatrixXd sigma = spread.At(spec, calibration);
  w.calibration_rows = y.rows();
  for (const auto& [mode, yhat] : sysid::ModePredictions(spec, calibration, predict, horizon)) {
    Eigen::VectorXd half(y.cols());
    for (Eigen::Index o = 0; o < y.cols(); ++o)
      half(o) = ConformalHalfWidth(y.col(o), yhat.col(o), sigma.col(o), level);
    w.half_width[mode] = half;
  }
  return w;
}

Eigen::MatrixXd IntervalWidths::HalfWidths(const std::string& mode,
                                           const Eigen::MatrixXd& sigma) const {
  const auto it = half_width.find(mode);
  if (it == half_width.end()) return {};
  Eigen::MatrixXd h = sigma;
  for (Eigen::Index o = 0; o < h.cols(); ++o) h.col(o) *= it->second(o);
  return h;
}

nlohmann::json IntervalScore(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& yhat,
                             const Eigen::Ref<const Eigen::VectorXd>& half_width,
                             const IntervalWidths& widths) {
  metrics::IntervalTally tally;
  for (Eigen::Index r = 0; r < y.size(); ++r) tally.Add(y(r), yhat(r), half_width(r));
  nlohmann::json j = tally.ToJson();
  j.erase("samples");
  j["level"] = widths.level;
  j["calibration_rows"] = widths.calibration_rows;
  return j;
}

}  // namespace odonata::fit

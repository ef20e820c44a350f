#pragma once
// How far to trust a prediction (issue 60 point 1; docs/identifier.md §7.6): split-conformal
// intervals around odonata-fit's predictions, one step, K steps ahead and in free run.
//
// Calibration: the residuals of the selection's chosen candidate — trained on the fit slice, so
// it never saw them — on the rows it was judged on (the training file's end, or the --select
// file). Per output and mode, with n finite residuals, the half width is the ⌈(n + 1)·level⌉-th
// smallest |residual| (infinite when that exceeds n): for a flight exchangeable with those rows,
// a new residual is at most that with probability ≥ level. The final model is trained on every
// row, so it usually predicts better than the candidate: the intervals lean wide. What they do
// not promise: coverage on a flight unlike the calibration rows (another regime, another
// vehicle), and a width that varies with the regime (one width per output and mode).

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "sysid/model/free_run.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit {

inline constexpr double kDefaultIntervalLevel = 0.9;

struct IntervalWidths {
  double level = kDefaultIntervalLevel;
  Eigen::Index calibration_rows = 0;  ///< targets the half widths were taken from
  /// Per mode ("one_step", "k_step", "free_run"), per output: the half width in raw units.
  std::map<std::string, Eigen::VectorXd> half_width;
};

/// The half widths from `predict`'s residuals on `calibration`, a series it did not train on;
/// `horizon` as odonata-fit's (> 1 adds k_step); free run only with output lags.
/// @throws std::invalid_argument for a level outside (0, 1).
IntervalWidths CalibrateIntervals(const sysid::RegressorSpec& spec,
                                  const sysid::Series& calibration, const sysid::Predictor& predict,
                                  int horizon, double level);

/// {level, coverage, mean_width, calibration_rows} of the interval ŷ ± `half_width` around one
/// output's predictions in one mode (Evaluate's "interval"): the share of targets within it, and
/// its mean width (raw units). A prediction that is not finite is not covered.
nlohmann::json IntervalScore(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& yhat, double half_width,
                             const IntervalWidths& widths);

}  // namespace odonata::fit

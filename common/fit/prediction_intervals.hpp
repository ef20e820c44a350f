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
// vehicle).
//
// Local widths: with a LocalSpread σ̂(x) (local_spread.hpp) the residuals are normalised,
// |residual| / σ̂(x), and the half width at a target is that quantile times σ̂ there — the same
// guarantee, the width where the rules fitted loosely or saw little (normalised conformal
// prediction, Papadopoulos et al. 2008).

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "fit/local_spread.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit {

inline constexpr double kDefaultIntervalLevel = 0.9;

struct IntervalWidths {
  double level = kDefaultIntervalLevel;
  Eigen::Index calibration_rows = 0;  ///< targets the half widths were taken from
  /// Per mode ("one_step", "k_step", "free_run"), per output: the half width in units of σ̂ (raw
  /// units without a fitted spread, where σ̂ = 1).
  std::map<std::string, Eigen::VectorXd> half_width;
  LocalSpread spread;  ///< σ̂(x); not fitted: one width per output and mode

  /// Each target's half width in `mode` (targets × outputs, raw units) from σ̂ at the targets
  /// of a series (LocalSpread::At); empty when the mode was not calibrated.
  Eigen::MatrixXd HalfWidths(const std::string& mode, const Eigen::MatrixXd& sigma) const;
};

/// The half widths from `predict`'s residuals on `calibration`, a series it did not train on,
/// each normalised by `spread` (not fitted: σ̂ = 1); `horizon` as odonata-fit's (> 1 adds
/// k_step); free run only with output lags.
/// @throws std::invalid_argument for a level outside (0, 1).
IntervalWidths CalibrateIntervals(const sysid::RegressorSpec& spec,
                                  const sysid::Series& calibration, const sysid::Predictor& predict,
                                  int horizon, double level, const LocalSpread& spread = {});

/// {level, coverage, mean_width, calibration_rows} of the intervals ŷ ± `half_width` (per
/// target) around one output's predictions in one mode (Evaluate's "interval"): the share of
/// targets within them, and their mean width (raw units). A prediction that is not finite is not
/// covered.
nlohmann::json IntervalScore(const Eigen::Ref<const Eigen::VectorXd>& y,
                             const Eigen::Ref<const Eigen::VectorXd>& yhat,
                             const Eigen::Ref<const Eigen::VectorXd>& half_width,
                             const IntervalWidths& widths);

}  // namespace odonata::fit

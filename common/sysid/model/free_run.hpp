#pragma once
// Parallel (free-run) simulation: the model fed its own past predictions (docs/identifier.md §7).

#include <functional>
#include <map>
#include <string>

#include <Eigen/Core>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

/// Maps a raw regressor to the raw predicted outputs (one per output signal).
using Predictor = std::function<Eigen::VectorXd(const Eigen::VectorXd& regressor)>;

/// One-step-ahead predictions from measured past outputs: rows t = first_target() … T − 1.
Eigen::MatrixXd PredictOneStep(const RegressorSpec& spec, const Series& series,
                               const Predictor& predict);

/// Free-run simulation: the first first_target() samples are measured, every later output lag
/// is the model's own prediction; inputs are always measured. Same rows as PredictOneStep.
/// A non-finite prediction is held at the last finite value so one diverging model cannot
/// poison the report with NaN; `diverged` (optional) tells the caller it happened.
Eigen::MatrixXd SimulateFreeRun(const RegressorSpec& spec, const Series& series,
                                const Predictor& predict, bool* diverged = nullptr);

/// K-step-ahead predictions ŷ(t | t − K): for each target t, a free run started from the measured
/// outputs before t − K + 1 (or its segment's start), K steps long. K = 1 is PredictOneStep; a
/// K beyond the segment is its free run. Same rows as PredictOneStep; `diverged` as there.
/// `stride` m > 1 predicts only every m-th target, counted back from the last (the others' rows
/// are left NaN): K/m of the cost, for a score that may sample the targets.
/// @pre horizon ≥ 1, stride ≥ 1.
Eigen::MatrixXd PredictAhead(const RegressorSpec& spec, const Series& series,
                             const Predictor& predict, int horizon, bool* diverged = nullptr,
                             int stride = 1);

/// The predictions of each mode a model is scored and its intervals calibrated in, by name:
/// "one_step"; with output lags "free_run", and with a horizon K > 1 "k_step" (PredictAhead).
/// Rows as PredictOneStep's.
std::map<std::string, Eigen::MatrixXd> ModePredictions(const RegressorSpec& spec,
                                                       const Series& series,
                                                       const Predictor& predict, int horizon);

}  // namespace odonata::sysid

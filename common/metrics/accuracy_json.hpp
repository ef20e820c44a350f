#pragma once
// Accuracy as JSON, the one shape every report and summary uses; non-finite values become null.

#include <nlohmann/json.hpp>

#include "metrics/accuracy.hpp"

namespace odonata::metrics {

/// {"fit", "vaf", "rmse", "ndei", "samples"}; NaN/Inf (a constant signal) are written as null.
nlohmann::json AccuracyToJson(const Accuracy& a);

/// AccuracyToJson, with "diverged": true where the FIT says so (FitDiverges): a prediction's
/// score, as every report prints it.
nlohmann::json ScoreToJson(const Accuracy& a);

}  // namespace odonata::metrics

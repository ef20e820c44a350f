#pragma once
// odonata-fit's scoring and data helpers, apart from the job's orchestration (fit_job.cpp) and
// its text report (fit_report_text.cpp): loading a record, scoring a predictor in every mode
// and the predictions file.

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/fit_job.hpp"
#include "fit/prediction_intervals.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::fit {

/// One data file as a series of the spec's signals, under the rules for real logs; what was
/// bridged or cut goes into `data` (and a warning).
sysid::Series LoadSeries(const std::string& path, const FitJobOptions& o,
                         const sysid::RegressorSpec& spec, nlohmann::json* data,
                         nlohmann::json* warnings);

/// Scores a predictor on a series in both modes, one block per output; with `widths`, each mode
/// they calibrate gets its prediction interval's score (IntervalScore) from the same predictions.
std::vector<nlohmann::json> Evaluate(const sysid::RegressorSpec& spec, const sysid::Series& s,
                                     const sysid::Predictor& predict, int horizon,
                                     const IntervalWidths* widths = nullptr);

/// Persistence ŷ(t) = y(t−1) one step ahead, y(t−K) K steps ahead (horizon K > 1); free run
/// holds the last measured value before each segment's first target. One block per output.
std::vector<nlohmann::json> EvaluatePersistence(const sysid::RegressorSpec& spec,
                                                const sysid::Series& s, int horizon);

/// Writes sample-by-sample predictions of the model and of ARX, both modes, for each data set.
/// One output keeps the plain column names; several get one set of columns per output (_NAME).
/// With a horizon K (> 1), fuzzy_k_step and arx_k_step follow: each a free run of K samples from
/// the measured outputs before it. With `widths`, each fuzzy mode's interval follows the output's
/// columns: fuzzy_one_step_lower, fuzzy_one_step_upper, … (prediction_intervals.hpp).
void WritePredictions(const std::string& path, const sysid::RegressorSpec& spec,
                      const std::vector<std::pair<std::string, const sysid::Series*>>& sets,
                      const sysid::Predictor& fuzzy, const sysid::Predictor& arx, int horizon,
                      const IntervalWidths* widths = nullptr);

}  // namespace odonata::fit

#pragma once
// What `odonata-fit --plot DIR` draws, as data (docs/guide/offline-tool.md, "Pictures"): the
// model, its readable form and the report, which rule of the readable form fires when along the
// validation run (a rule-activation strip under the traces), and for a static map the output
// over its two most influential inputs (the paper's F̄_z(f, φ₀)). The firing is the model's own
// (GaussianRuleBase::Evaluate), so the pictures never re-implement it; fit_plots.py draws.

#include <string>

#include <nlohmann/json.hpp>

#include "sysid/model/narx_model.hpp"
#include "sysid/model/readable_model.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit {

/// Writes into `dir` (created if missing): model.json, readable_model.json (when `readable`),
/// report.json, activation.csv over `run` (sample, t_s, measured, one_step, free_run, then each
/// readable rule's normalised firing, first output), and surface.csv for a model without output
/// lags, or gain_surface.csv for a dynamic one of several linear rules (its steady-state gains
/// over the two signals its rules spread over most, the rules blended by their firing).
/// `sample_time_s` 0: t_s is the sample index. @throws std::runtime_error naming a file that cannot
/// be written.
void WritePlotData(const std::string& dir, const sysid::NarxModel& model,
                   const sysid::ReadableModel* readable, const sysid::Series& run,
                   double sample_time_s, const nlohmann::json& report);

/// Draws the pictures of `dir` with fit_plots.py (python3 and matplotlib): membership.png,
/// activation.png, and surface.png or gain_schedule.png. Returns the files written.
/// @throws std::runtime_error when the script cannot be found or fails (the data stay).
std::vector<std::string> DrawPlots(const std::string& dir);

/// Writes `dir`/index.html with fit_report.py from what the fit wrote there (report.json, the
/// pictures, predictions.csv, command.txt): the page of odonata-fit --report. Returns its path.
/// @throws std::runtime_error when the script cannot be found or fails (the data stay).
std::string WriteReportPage(const std::string& dir);

}  // namespace odonata::fit

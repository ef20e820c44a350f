#pragma once
// The parts of odonata-fit's --json report that describe how the model was made: the selection
// (candidates, the checks against the linear model), the training, the settings carried to the
// online identifier. Scores live in fit_scoring.hpp, the text report in fit_report_text.hpp.

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/fit_job.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::fit {

nlohmann::json StagesToJson(const std::vector<sysid::SimulationStage>& stages);

nlohmann::json CandidateToJson(const sysid::Candidate& c);

/// The selection's record: criterion, tolerances, slices, every candidate, the chosen one and
/// the checks against the linear model. `scored_on`: the selection file, or empty (a hold-out).
nlohmann::json SelectionToJson(const sysid::OfflineFit& fit, const sysid::SelectionOptions& so,
                               const std::string& scored_on, Eigen::Index training_rows);

/// Each epoch of the final training: accepted or not, the training FIT, the rules.
nlohmann::json EpochHistoryToJson(const sysid::TrainReport& report);

/// What the replayed online identifier's refits did (FitJobOptions::refit).
nlohmann::json RefitsToJson(const sysid::OnlineReplay& replay, const sysid::RegressorSpec& spec);

/// The model's structure and learner settings at the report's top level.
void PutModelSettings(const FitJobOptions& o, const sysid::NarxModel& model,
                      const sysid::TrainOptions& trained_with, nlohmann::json& report);

/// Output k's rules, their local linear models, the readable form's text and the global linear
/// model (docs/identifier.md §7.4, §7.5); time constants in seconds when sample_time_s > 0.
void PutRuleDescriptions(const sysid::NarxModel& model, int k, const sysid::ReadableModel* readable,
                         double sample_time_s, nlohmann::json& per_output);
/// Each rule's parameter uncertainty (sysid/estimation/local_model_uncertainty.hpp) from the
/// training series: "uncertainty" in every local_models entry, and the readable form's rules
/// with their standard errors in readable.uncertainty (sentences).
void PutUncertainty(const sysid::NarxModel& model, int k, const sysid::ReadableModel* readable,
                    const sysid::Series& train, double sample_time_s, nlohmann::json& per_output);

}  // namespace odonata::fit

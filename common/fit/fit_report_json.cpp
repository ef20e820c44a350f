#include "fit/fit_report_json.hpp"

#include <cmath>

#include "io/json_number.hpp"
#include "sysid/estimation/local_model_uncertainty.hpp"
#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/readable_model.hpp"
#include "sysid/model/rule_listing.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::fit {
namespace {

nlohmann::json Numbers(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const double x : v) a.push_back(io::FiniteOrNull(x));
  return a;
}

nlohmann::json LinearCheckToJson(const sysid::LinearCheck& lc) {
  return nlohmann::json{{"candidate_index", lc.candidate},
                        {"folds", lc.fuzzy_folds.size()},
                        {"fuzzy_ndei", io::FiniteOrNull(lc.fuzzy_score)},
                        {"linear_ndei", io::FiniteOrNull(lc.linear_score)},
                        {"fuzzy_folds", Numbers(lc.fuzzy_folds)},
                        {"linear_folds", Numbers(lc.linear_folds)},
                        {"margin", lc.margin},
                        {"linear_chosen", lc.linear_chosen}};
}

}  // namespace

nlohmann::json StagesToJson(const std::vector<sysid::SimulationStage>& stages) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& st : stages) {
    nlohmann::json j = {{"horizon", st.horizon}, {"steps", st.steps}};
    if (st.gauss_newton) j["levenberg_marquardt"] = true;
    if (st.from_linear) j["from_linear"] = true;
    a.push_back(j);
  }
  return a;
}

nlohmann::json CandidateToJson(const sysid::Candidate& c) {
  return {{"consequent", fuzzy::ToString(c.consequent)},
          {"linear", c.linear},
          {"simulation", StagesToJson(c.simulation)},
          {"entropy_threshold", c.threshold},
          {"kappa", c.kappa},
          {"deviation_ridge", c.deviation_ridge},
          {"epochs", c.epochs},
          {"rules", c.rules},
          {"at_cap", c.at_cap},
          {"holdout_one_step_ndei", io::FiniteOrNull(c.holdout_one_step_ndei)},
          {"holdout_free_run_ndei", io::FiniteOrNull(c.holdout_free_run_ndei)},
          {"holdout_ahead_ndei", io::FiniteOrNull(c.holdout_ahead_ndei)},
          {"score", io::FiniteOrNull(c.score)},
          {"rest_deviation", io::FiniteOrNull(c.rest_deviation)},
          {"restless", c.restless},
          {"one_step_lost", c.one_step_lost}};
}

nlohmann::json SelectionToJson(const sysid::OfflineFit& fit, const sysid::SelectionOptions& so,
                               const std::string& scored_on, Eigen::Index training_rows) {
  const sysid::SelectionResult& sel = *fit.selection;
  nlohmann::json cands = nlohmann::json::array();
  for (const auto& c : sel.candidates) cands.push_back(CandidateToJson(c));
  nlohmann::json j = {{"criterion", sel.criterion_horizon == 0   ? "free_run"
                                    : sel.criterion_horizon == 1 ? "one_step"
                                                                 : "k_step"},
                      {"criterion_horizon", sel.criterion_horizon},
                      {"one_step_bound", io::FiniteOrNull(sel.one_step_bound)},
                      {"scored_on", scored_on.empty() ? "training hold-out" : scored_on},
                      {"relative_tolerance", so.relative_tolerance},
                      {"absolute_tolerance", so.absolute_tolerance},
                      {"fit_samples", sel.fit_samples},
                      {"searched_rows", fit.searched_rows},
                      {"training_rows", training_rows},
                      {"holdout_samples", sel.holdout_samples},
                      {"candidates", cands},
                      {"best_index", sel.best},
                      {"chosen_index", sel.chosen}};
  if (sel.linear_check.done) {
    // The one that decided, and every check made (the candidates that lost first).
    j["linear_check"] = LinearCheckToJson(sel.linear_check);
    nlohmann::json all = nlohmann::json::array();
    for (const auto& lc : sel.linear_checks) all.push_back(LinearCheckToJson(lc));
    j["linear_checks"] = all;
  }
  if (sel.output_error_check.done) {
    const auto& oc = sel.output_error_check;
    j["linear_fit_check"] = {
        {"folds", oc.fuzzy_folds.size()},
        {"output_error_ndei", io::FiniteOrNull(oc.fuzzy_score)},
        {"one_step_ndei", io::FiniteOrNull(oc.linear_score)},
        {"output_error_folds", Numbers(oc.fuzzy_folds)},
        {"one_step_folds", Numbers(oc.linear_folds)},
        {"standard_error", sysid::PairedStandardError(oc.fuzzy_folds, oc.linear_folds)},
        {"output_error_kept", sel.output_error_linear}};
  }
  return j;
}

nlohmann::json EpochHistoryToJson(const sysid::TrainReport& report) {
  nlohmann::json hist = nlohmann::json::array();
  for (const auto& e : report.epochs)
    hist.push_back({{"epoch", e.epoch},
                    {"accepted", e.accepted},
                    {"train_fit", e.train_fit},
                    {"rules", e.rules}});
  return hist;
}

nlohmann::json RefitsToJson(const sysid::OnlineReplay& replay, const sysid::RegressorSpec& spec) {
  nlohmann::json seen = nlohmann::json::array();
  for (std::size_t o = 0; o < replay.settling.size() && o < spec.outputs.size(); ++o) {
    seen.push_back({{"output", spec.outputs[o]},
                    {"state", sysid::SettlingStateName(replay.settling[o].state)},
                    {"sentence", replay.settling[o].sentence}});
  }
  return {{"landed", replay.refits},
          {"failed", replay.failed_refits},
          {"samples_learned", replay.samples_learned},
          {"incumbents_kept", replay.incumbents_kept},
          {"steady_state_refused", replay.steady_state_refused},
          {"linear_landed", replay.linear_landed},
          {"seen_enough", seen}};
}

void PutModelSettings(const FitJobOptions& o, const sysid::NarxModel& model,
                      const sysid::TrainOptions& trained_with, nlohmann::json& report) {
  const sysid::RegressorSpec& spec = model.spec();
  const auto& fm = model.model(0);
  report["output"] = spec.outputs.at(0);
  report["inputs"] = spec.inputs;
  report["regressors"] = spec.RegressorNames();
  report["target"] = spec.TargetName(0);
  report["ny"] = spec.output_lags;
  report["nu"] = spec.input_lags;
  report["delay"] = spec.delay;
  report["rules"] = fm.rules();
  report["entropy_threshold"] = fm.config().entropy.threshold;
  report["kappa"] = fm.config().entropy.kappa;
  report["max_rules"] = fm.config().entropy.max_rules;
  report["consequent"] = fuzzy::ToString(fm.consequent().kind());
  report["epochs"] = o.load_model.empty() ? trained_with.epochs : 0;
  report["least_squares_refinement"] = o.load_model.empty() && o.train.refine_least_squares;
  report["deviation_ridge"] = trained_with.deviation_ridge;
  report["min_rule_support"] = trained_with.min_rule_support;
  report["seed"] = o.seed;
}

void PutRuleDescriptions(const sysid::NarxModel& model, int k, const sysid::ReadableModel* readable,
                         double sample_time_s, nlohmann::json& per_output) {
  const sysid::RegressorSpec& spec = model.spec();
  const auto& fk = model.model(k);
  per_output["rules"] = fk.rules();
  per_output["consequent"] = fuzzy::ToString(fk.consequent().kind());
  per_output["target"] = spec.TargetName(k);
  per_output["rule_text"] = sysid::DescribeRules(model, k, sample_time_s);
  if (readable) {
    const auto index = static_cast<std::size_t>(k);
    per_output["readable"] = {{"rules", readable->model.model(k).rules()},
                              {"linear", static_cast<bool>(readable->linear[index])},
                              {"text", readable->sentences[index]}};
  }
  // Each rule's linear local model as a control engineer reads it (docs/identifier.md §7.4).
  nlohmann::json local = nlohmann::json::array();
  for (const auto& d : sysid::LocalModels(model, k, sample_time_s))
    local.push_back(sysid::ToJson(d, sample_time_s));
  per_output["local_models"] = local;
  if (const auto global = sysid::GlobalLinearModel(model, k))
    per_output["global_linear"] =
        sysid::ToJson(sysid::AnalyseDynamics(spec, k, *global, sample_time_s), sample_time_s);
}

void PutUncertainty(const sysid::NarxModel& model, int k, const sysid::ReadableModel* readable,
                    const sysid::Series& train, double sample_time_s, nlohmann::json& per_output) {
  const auto full = sysid::LocalModelUncertainty(model, k, train, sample_time_s);
  if (per_output.contains("local_models"))
    for (std::size_t j = 0; j < full.size() && j < per_output["local_models"].size(); ++j)
      per_output["local_models"][j]["uncertainty"] = sysid::ToJson(full[j], sample_time_s);
  if (!readable || !per_output.contains("readable")) return;
  const sysid::NarxModel& rm = readable->model;
  const auto mine = sysid::LocalModelUncertainty(rm, k, train, sample_time_s);
  nlohmann::json lines = nlohmann::json::array();
  for (std::size_t j = 0; j < mine.size(); ++j)
    lines.push_back("rule " + std::to_string(j + 1) + ": " +
                    sysid::DescribeWithUncertainty(rm.spec(), k, rm, static_cast<int>(j), mine[j],
                                                   sample_time_s));
  per_output["readable"]["uncertainty"] = lines;
}

}  // namespace odonata::fit

#include "fit_job.hpp"

#include "fit_plot_data.hpp"
#include "fit_scoring.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "metrics/accuracy.hpp"
#include "metrics/accuracy_alarm.hpp"
#include "metrics/accuracy_json.hpp"
#include "metrics/running_accuracy.hpp"
#include "progress_bar.hpp"
#include "records/record_file.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/quadratic_arx_model.hpp"
#include "sysid/model/readable_model.hpp"
#include "sysid/model/rule_listing.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/learner_settings.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/selection/offline_fit.hpp"

#include <fstream>

namespace odonata::fit {

nlohmann::json RunFitJob(const FitJobOptions& o) {
  sysid::RegressorSpec spec = o.spec;
  std::optional<sysid::NarxModel> model;
  if (!o.load_model.empty()) {
    model = sysid::NarxModel::Load(o.load_model);
    spec = model->spec();
  } else {
    spec.outputs = o.outputs;
    spec.inputs = o.inputs;
    const std::string problems = spec.Problems();
    if (!problems.empty()) throw std::runtime_error("invalid model structure: " + problems);
    const std::string config_problems = o.model.Problems();
    if (!config_problems.empty()) throw std::runtime_error(config_problems);
  }
  const std::string output = spec.outputs.at(0);
  const std::size_t n_outputs = spec.outputs.size();
  nlohmann::json report;
  nlohmann::json warnings = nlohmann::json::array();
  nlohmann::json data = nlohmann::json::object();
  std::optional<sysid::Series> train, validate;
  if (!o.train_csv.empty()) train = LoadSeries(o.train_csv, o, spec, &data, &warnings);
  if (!o.validate_csv.empty()) validate = LoadSeries(o.validate_csv, o, spec, &data, &warnings);
  if (!train && !model) throw std::runtime_error("nothing to do: give --train or --load-model");
  if (!o.track_csv.empty() && n_outputs > 1)
    throw std::runtime_error("--track follows one output; give one --output");
  ProgressBar bar(o.progress);
  fuzzy::FuzzyModelConfig cfg = o.model;
  sysid::TrainOptions topt = o.train;
  std::optional<sysid::Scaling> declared;
  if (!model && !o.ranges.empty()) {
    std::ifstream in(o.ranges);
    if (!in) throw std::runtime_error(o.ranges + ": cannot open ranges file");
    nlohmann::json j;
    try {
      in >> j;
      declared = sysid::ScalingFromRanges(spec, sysid::RangesFromJson(j));
    } catch (const std::exception& e) {
      throw std::runtime_error(o.ranges + ": " + e.what());
    }
    topt.fit_scaling = false;
  }
  const bool search = !model && !o.refit.enabled() && o.select &&
                      !(o.consequent_given && o.threshold_given && o.kappa_given && o.epochs_given);
  if (!o.save_ranges.empty() && train) {
    std::ofstream out(o.save_ranges);
    out << sysid::RangesToJson(sysid::RangesFromSeries(spec, *train)).dump(1) << "\n";
    if (!out) throw std::runtime_error(o.save_ranges + ": cannot write");
  }
  if (!search && o.simulation_given && o.train.refine_least_squares) topt.simulation = o.simulation;
  if (!model && o.refit.enabled()) {
    // The online identifier's learner, replayed: every row in order through the same class, with
    // its scheduled refits and the refit that closes learning (docs/identifier.md §6.3). With
    // --horizon, they choose by what is reported, as the identifier's refit_horizon.
    sysid::RefitSchedule refit = o.refit;
    refit.horizon = o.horizon;
    sysid::OnlineReplay replay = sysid::LearnOnline(sysid::NarxModel(spec, cfg), refit, *train,
                                                    declared, !o.replay_unfrozen);
    report["refits"] = {{"landed", replay.refits},
                        {"failed", replay.failed_refits},
                        {"samples_learned", replay.samples_learned},
                        {"incumbents_kept", replay.incumbents_kept},
                        {"steady_state_refused", replay.steady_state_refused},
                        {"linear_landed", replay.linear_landed}};
    model.emplace(std::move(replay.model));
  } else if (!model) {
    sysid::OfflineFitOptions fo;
    fo.search = search;
    fo.epochs_given = o.epochs_given;
    fo.scaling = declared;
    fo.search_budget = o.search_budget;
    if (search) {
      sysid::SelectionOptions& so = fo.selection;
      so = o.selection;
      if (o.consequent_given) so.consequents = {cfg.consequent};
      if (o.threshold_given) so.thresholds = {cfg.entropy.threshold};
      if (o.kappa_given) so.kappas = {cfg.entropy.kappa};
      if (o.epochs_given) {
        so.max_epochs = o.train.epochs;
        so.patience = 0;
      }
      if (o.train.refine_least_squares) so.simulation = o.simulation;
      so.horizon = o.horizon;
    }
    std::optional<sysid::Series> select_series;
    if (search && !o.select_csv.empty())
      select_series = LoadSeries(o.select_csv, o, spec, &data, &warnings);
    int total_epochs = 1;
    fo.on_training = [&total_epochs](int epochs) { total_epochs = epochs; };
    topt.progress = [&bar, &total_epochs](int epoch, long sample, long total) {
      bar.Update("epoch " + std::to_string(epoch + 1) + "/" + std::to_string(total_epochs),
                 (epoch + double(sample) / double(total)) / total_epochs);
    };
    sysid::OfflineFit fit = sysid::FitOffline(
        spec, cfg, topt, *train, fo,
        [&bar](const sysid::Candidate& c, std::size_t k, std::size_t n) {
          char label[96];
          std::snprintf(label, sizeof label, "selecting %s H=%.3g k=%.2g: %d rules",
                        fuzzy::ToString(c.consequent), c.threshold, c.kappa, c.rules);
          bar.Update(label, double(k) / double(n));
        },
        select_series ? &*select_series : nullptr);
    if (fit.selection) {
      const auto& sel = *fit.selection;
      const auto& so = fo.selection;
      nlohmann::json cands = nlohmann::json::array();
      for (const auto& c : sel.candidates) cands.push_back(CandidateToJson(c));
      report["selection"] = {
          {"criterion", sel.criterion_horizon == 0   ? "free_run"
                        : sel.criterion_horizon == 1 ? "one_step"
                                                     : "k_step"},
          {"criterion_horizon", sel.criterion_horizon},
          {"one_step_bound", std::isfinite(sel.one_step_bound) ? nlohmann::json(sel.one_step_bound)
                                                               : nlohmann::json(nullptr)},
          {"scored_on", o.select_csv.empty() ? "training hold-out" : o.select_csv},
          {"relative_tolerance", so.relative_tolerance},
          {"absolute_tolerance", so.absolute_tolerance},
          {"fit_samples", sel.fit_samples},
          {"searched_rows", fit.searched_rows},
          {"training_rows", train->samples()},
          {"holdout_samples", sel.holdout_samples},
          {"candidates", cands},
          {"best_index", sel.best},
          {"chosen_index", sel.chosen}};
      auto nums = [](const std::vector<double>& v) {
        nlohmann::json a = nlohmann::json::array();
        for (const double x : v) a.push_back(std::isfinite(x) ? nlohmann::json(x) : nullptr);
        return a;
      };
      if (sel.linear_check.done) {
        auto check = [&](const sysid::LinearCheck& lc) {
          return nlohmann::json{
              {"candidate_index", lc.candidate},
              {"folds", lc.fuzzy_folds.size()},
              {"fuzzy_ndei",
               std::isfinite(lc.fuzzy_score) ? nlohmann::json(lc.fuzzy_score) : nullptr},
              {"linear_ndei",
               std::isfinite(lc.linear_score) ? nlohmann::json(lc.linear_score) : nullptr},
              {"fuzzy_folds", nums(lc.fuzzy_folds)},
              {"linear_folds", nums(lc.linear_folds)},
              {"margin", lc.margin},
              {"linear_chosen", lc.linear_chosen}};
        };
        // The one that decided, and every check made (the candidates that lost first).
        report["selection"]["linear_check"] = check(sel.linear_check);
        nlohmann::json all = nlohmann::json::array();
        for (const auto& lc : sel.linear_checks) all.push_back(check(lc));
        report["selection"]["linear_checks"] = all;
      }
      if (sel.output_error_check.done) {
        const auto& oc = sel.output_error_check;
        report["selection"]["linear_fit_check"] = {
            {"folds", oc.fuzzy_folds.size()},
            {"output_error_ndei",
             std::isfinite(oc.fuzzy_score) ? nlohmann::json(oc.fuzzy_score) : nullptr},
            {"one_step_ndei",
             std::isfinite(oc.linear_score) ? nlohmann::json(oc.linear_score) : nullptr},
            {"output_error_folds", nums(oc.fuzzy_folds)},
            {"one_step_folds", nums(oc.linear_folds)},
            {"standard_error", sysid::PairedStandardError(oc.fuzzy_folds, oc.linear_folds)},
            {"output_error_kept", sel.output_error_linear}};
      }
      for (const auto& w : sel.warnings) warnings.push_back(w);
    }
    cfg = fit.config;
    topt.epochs = fit.train.epochs;
    nlohmann::json hist = nlohmann::json::array();
    for (const auto& e : fit.report.epochs)
      hist.push_back({{"epoch", e.epoch},
                      {"accepted", e.accepted},
                      {"train_fit", e.train_fit},
                      {"rules", e.rules}});
    report["epoch_history"] = hist;
    report["simulation"] = StagesToJson(fit.report.simulation);
    topt.deviation_ridge = fit.train.deviation_ridge;
    model.emplace(std::move(fit.model));
  }
  bar.Finish();
  const sysid::Predictor predict = [&model](const Eigen::VectorXd& x) { return model->Predict(x); };
  const auto& fm = model->model(0);
  report["output"] = output;
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
  report["epochs"] = o.load_model.empty() ? topt.epochs : 0;
  report["least_squares_refinement"] = o.load_model.empty() && o.train.refine_least_squares;
  report["deviation_ridge"] = topt.deviation_ridge;
  report["min_rule_support"] = topt.min_rule_support;
  report["seed"] = o.seed;
  // Scores per output: the first output's at the top level (as with one output), every output's
  // under per_output when there are several.
  std::vector<nlohmann::json> per(n_outputs, nlohmann::json::object());
  const auto put = [&per](const std::vector<nlohmann::json>& blocks, const std::string& where,
                          const std::string& key) {
    for (std::size_t k = 0; k < blocks.size(); ++k) {
      if (where.empty())
        per[k][key] = blocks[k];
      else
        per[k]["baselines"][where][key] = blocks[k];
    }
  };
  if (train) put(Evaluate(spec, *train, predict, o.horizon), "", "train");
  if (validate) put(Evaluate(spec, *validate, predict, o.horizon), "", "validate");
  // Time constants in seconds when the training data's rate is known (a time column or a ULog).
  double sample_time_s = 0;
  if (!o.train_csv.empty() && data.contains(o.train_csv) && data[o.train_csv].contains("rate_hz"))
    sample_time_s = 1.0 / data[o.train_csv]["rate_hz"].get<double>();
  // The readable form (docs/identifier.md §7.5) is a model too: scored beside the full one, its
  // cost a FIT figure.
  std::optional<sysid::ReadableModel> readable;
  if (train) {
    try {
      sysid::ReadableOptions ro;
      ro.criterion_horizon = o.horizon;
      readable = sysid::MakeReadable(*model, *train, sample_time_s, ro);
      const sysid::NarxModel& rm = readable->model;
      const sysid::Predictor readable_predict = [&rm](const Eigen::VectorXd& x) {
        return rm.Predict(x);
      };
      put(Evaluate(spec, *train, readable_predict, o.horizon), "readable", "train");
      if (validate)
        put(Evaluate(spec, *validate, readable_predict, o.horizon), "readable", "validate");
    } catch (const std::exception& e) {
      warnings.push_back(std::string("no readable form: ") + e.what());
    }
  }
  if (train) {
    const auto arx = sysid::ArxModel::Fit(spec, *train);
    const sysid::Predictor arx_predict = [&arx](const Eigen::VectorXd& x) {
      return arx.Predict(x);
    };
    put(Evaluate(spec, *train, arx_predict, o.horizon), "arx", "train");
    put(EvaluatePersistence(spec, *train), "persistence", "train");
    // ARX with squared inputs: whether a static input nonlinearity explains the fuzzy model's
    // gain (only with inputs: without them it is ARX).
    std::optional<sysid::QuadraticArxModel> quadratic;
    if (!spec.inputs.empty() && spec.input_lags > 0) {
      quadratic = sysid::QuadraticArxModel::Fit(spec, *train);
    }
    const sysid::Predictor quadratic_predict = [&quadratic](const Eigen::VectorXd& x) {
      return quadratic->Predict(x);
    };
    if (quadratic)
      put(Evaluate(spec, *train, quadratic_predict, o.horizon), "arx_squared_inputs", "train");
    if (validate) {
      put(Evaluate(spec, *validate, arx_predict, o.horizon), "arx", "validate");
      if (quadratic)
        put(Evaluate(spec, *validate, quadratic_predict, o.horizon), "arx_squared_inputs",
            "validate");
      put(EvaluatePersistence(spec, *validate), "persistence", "validate");
      // Warnings only: the validation data informs the reader, never a choice.
      for (std::size_t k = 0; k < n_outputs; ++k) {
        const auto& v = per[k]["validate"];
        for (const char* base : {"arx", "persistence"}) {
          for (const char* mode : {"one_step", "free_run", "k_step"}) {
            const auto& b = per[k]["baselines"][base]["validate"];
            if (!v.contains(mode) || !b.contains(mode)) continue;
            const auto& fz = v[mode]["fit"];
            const auto& bf = b[mode]["fit"];
            // Below a hundredth of a point it is the same model (ARX chosen as the linear one).
            if (fz.is_number() && bf.is_number() && fz.get<double>() < bf.get<double>() - 0.01) {
              char line[200];
              std::snprintf(line, sizeof line,
                            "%s%sthe model loses to %s on validation (%s FIT %.2f %% < %.2f %%)",
                            n_outputs > 1 ? spec.outputs[k].c_str() : "", n_outputs > 1 ? ": " : "",
                            base, mode, fz.get<double>(), bf.get<double>());
              warnings.push_back(line);
            }
          }
        }
      }
    }
    if (!o.track_csv.empty()) {
      const sysid::Series track = LoadSeries(o.track_csv, o, spec, nullptr, &warnings);
      report["track"] =
          Track(spec, track, *model, arx, o.track_output, o.track_window, o.track_forgetting);
    }
    if (!o.predictions.empty()) {
      std::vector<std::pair<std::string, const sysid::Series*>> sets{{"train", &*train}};
      if (validate) sets.emplace_back("validate", &*validate);
      WritePredictions(o.predictions, spec, sets, predict, arx_predict, o.horizon);
      report["predictions_file"] = o.predictions;
    }
  }
  for (std::size_t k = 0; k < n_outputs; ++k) {
    const auto& fk = model->model(static_cast<int>(k));
    const int out = static_cast<int>(k);
    per[k]["rules"] = fk.rules();
    per[k]["consequent"] = fuzzy::ToString(fk.consequent().kind());
    per[k]["target"] = spec.TargetName(out);
    per[k]["rule_text"] = sysid::DescribeRules(*model, out, sample_time_s);
    if (readable) {
      per[k]["readable"] = {{"rules", readable->model.model(out).rules()},
                            {"linear", static_cast<bool>(readable->linear[k])},
                            {"text", readable->sentences[k]}};
    }
    // Each rule's linear local model as a control engineer reads it (docs/identifier.md §7.4).
    nlohmann::json local = nlohmann::json::array();
    for (const auto& d : sysid::LocalModels(*model, out, sample_time_s))
      local.push_back(sysid::ToJson(d, sample_time_s));
    per[k]["local_models"] = local;
    if (const auto global = sysid::GlobalLinearModel(*model, out))
      per[k]["global_linear"] =
          sysid::ToJson(sysid::AnalyseDynamics(spec, out, *global, sample_time_s), sample_time_s);
  }
  // The first output at the top level, as a one-output report always had it.
  for (const char* key :
       {"train", "validate", "baselines", "rule_text", "local_models", "readable"})
    if (per[0].contains(key)) report[key] = per[0][key];
  report["outputs"] = spec.outputs;
  if (n_outputs > 1) {
    for (std::size_t k = 0; k < n_outputs; ++k) report["per_output"][spec.outputs[k]] = per[k];
  }
  report["warnings"] = warnings;
  report["data"] = data;
  if (!o.save_config.empty() && train) {
    // The choices carried over to the online identifier: odonata-identifier --config takes this
    // as it is (identifier_config.cpp's keys).
    const auto& fm0 = model->model(0).config();
    nlohmann::json c;
    c["instance"] = "identifier";
    c["outputs"] = spec.outputs;
    c["inputs"] = spec.inputs;
    c["ny"] = spec.output_lags;
    c["nu"] = spec.input_lags;
    c["delay"] = spec.delay;
    // The learner's settings as chosen here, its refits choosing as this fit did: K steps ahead
    // with --horizon K (learner_settings.hpp: the one writer of these keys).
    sysid::RefitSchedule refit = sysid::RefitSchedule::IdentifierDefault();
    refit.horizon = o.horizon;
    const nlohmann::ordered_json learner = sysid::LearnerSettingsJson(fm0, refit);
    for (const auto& [key, value] : learner.items()) c[key] = value;
    nlohmann::json ranges;
    if (!o.ranges.empty()) {
      std::ifstream in(o.ranges);
      in >> ranges;
    } else {
      ranges = sysid::RangesToJson(sysid::RangesFromSeries(spec, *train));
    }
    c["ranges"] = ranges;
    c["source"] = "signals";
    std::ofstream out(o.save_config);
    out << c.dump(2) << "\n";
    if (!out) throw std::runtime_error(o.save_config + ": cannot write");
    report["config_file"] = o.save_config;
  }
  if (!o.save_model.empty()) {
    model->Save(o.save_model);
    report["model_file"] = o.save_model;
  }
  if (!o.plot_dir.empty() && (validate || train)) {
    WritePlotData(o.plot_dir, *model, readable ? &*readable : nullptr,
                  validate ? *validate : *train, sample_time_s, report);
    try {
      report["plots"] = DrawPlots(o.plot_dir);
    } catch (const std::exception& e) {
      report["warnings"].push_back(std::string("no pictures: ") + e.what());
    }
  }
  return report;
}

}  // namespace odonata::fit

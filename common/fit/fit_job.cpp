#include "fit/fit_job.hpp"

#include "fit/fit_plot_data.hpp"
#include "fit/fit_report_json.hpp"
#include "fit/fit_scoring.hpp"
#include "fit/fit_tracking.hpp"
#include "fit/fit_verdict.hpp"
#include "fit/prediction_intervals.hpp"
#include "io/atomic_file.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "fit/progress_bar.hpp"
#include "identifier_config/identifier_config.hpp"
#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "metrics/accuracy.hpp"
#include "metrics/accuracy_alarm.hpp"
#include "metrics/accuracy_json.hpp"
#include "metrics/running_accuracy.hpp"
#include "records/record_file.hpp"
#include "sysid/estimation/local_model_uncertainty.hpp"
#include "sysid/model/arx_model.hpp"
#include "sysid/model/excitation.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/local_dynamics.hpp"
#include "sysid/model/quadratic_arx_model.hpp"
#include "sysid/model/readable_model.hpp"
#include "sysid/model/rule_listing.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"
#include "sysid/selection/offline_fit.hpp"

#include <fstream>

namespace odonata::fit {

namespace {

// The records a job reads, what was bridged or cut in them, and the warnings so far.
struct JobData {
  std::optional<sysid::Series> train, validate;
  // The selection's chosen candidate and the rows it was judged on, never trained on: what the
  // prediction intervals are calibrated on (prediction_intervals.hpp).
  std::optional<sysid::NarxModel> calibration_model;
  std::optional<sysid::Series> calibration;
  std::optional<sysid::Series> calibration_fit;     // the rows its model trained on: σ̂'s
  std::optional<IntervalWidths> widths;             // calibrated on them
  nlohmann::json files = nlohmann::json::object();  // per file: rate, bridged gaps, segments
  nlohmann::json warnings = nlohmann::json::array();
};

// The model to evaluate (--load-model) or the structure to train, checked.
sysid::RegressorSpec SpecFor(const FitJobOptions& o, std::optional<sysid::NarxModel>& model) {
  if (!o.load_model.empty()) {
    model = sysid::NarxModel::Load(o.load_model);
    return model->spec();
  }
  sysid::RegressorSpec spec = o.spec;
  spec.outputs = o.outputs;
  spec.inputs = o.inputs;
  // The output's own past is in the regressor already (--ny); as an input too, the model would
  // read y(k) to predict y(k) with --delay 0, or count it twice.
  for (const auto& out : spec.outputs)
    if (std::find(spec.inputs.begin(), spec.inputs.end(), out) != spec.inputs.end())
      throw std::runtime_error("'" + out +
                               "' is named as the output and as an input: its past "
                               "values are already regressors (--ny); leave it out of --input");
  const std::string problems = spec.Problems();
  if (!problems.empty()) throw std::runtime_error("invalid model structure: " + problems);
  const std::string config_problems = o.model.Problems();
  if (!config_problems.empty()) throw std::runtime_error(config_problems);
  return spec;
}

// The signal ranges in the file `path` (--ranges). @throws std::runtime_error naming the file.
sysid::SignalRanges ReadRanges(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open ranges file");
  nlohmann::json j;
  try {
    in >> j;
    return sysid::RangesFromJson(j);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

// The scaling fixed by --ranges.
sysid::Scaling DeclaredScaling(const FitJobOptions& o, const sysid::RegressorSpec& spec) {
  const sysid::SignalRanges ranges = ReadRanges(o.ranges);
  try {
    return sysid::ScalingFromRanges(spec, ranges);
  } catch (const std::exception& e) {
    throw std::runtime_error(o.ranges + ": " + e.what());
  }
}

// Selection (when searching) and training on all of --train, with progress on the bar; the
// selection's and the training's record go into the report.
sysid::NarxModel TrainOffline(const FitJobOptions& o, const sysid::RegressorSpec& spec, bool search,
                              const std::optional<sysid::Scaling>& declared,
                              fuzzy::FuzzyModelConfig& cfg, sysid::TrainOptions& topt, JobData& d,
                              ProgressBar& bar, nlohmann::json& report) {
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
    select_series = LoadSeries(o.select_csv, o, spec, &d.files, &d.warnings);
  // Each phase's time left is its own pace's, plus what the phases after it are expected to take.
  sysid::FinalTrainingEstimate final_training;
  fo.on_training = [&final_training](const sysid::FinalTrainingEstimate& e) { final_training = e; };
  topt.progress = [&bar, &final_training](int epoch, long sample, long total) {
    const int epochs = final_training.epochs;
    bar.Update("epoch " + std::to_string(epoch + 1) + "/" + std::to_string(epochs),
               (epoch + double(sample) / double(total)) / epochs,
               final_training.simulation_seconds);
  };
  topt.simulation_progress = [&bar](int stage, long done, long all) {
    bar.Update("simulation stage " + std::to_string(stage + 1),
               all > 0 ? double(done) / double(all) : 1.0);
  };
  sysid::OfflineFit fit = sysid::FitOffline(
      spec, cfg, topt, *d.train, fo,
      [&bar](const sysid::Candidate& c, const sysid::SelectionProgress& p) {
        char label[96];
        std::snprintf(label, sizeof label, "selecting %s H=%.3g k=%.2g: %d rules",
                      fuzzy::ToString(c.consequent), c.threshold, c.kappa, c.rules);
        bar.Update(label, p.fraction, p.final_seconds);
      },
      select_series ? &*select_series : nullptr);
  if (fit.selection) {
    report["selection"] = SelectionToJson(fit, fo.selection, o.select_csv, d.train->samples());
    for (const auto& w : fit.selection->warnings) d.warnings.push_back(w);
  }
  if (fit.selection && fit.selection->chosen_model && fit.selection->holdout_samples > 0) {
    d.calibration_model = fit.selection->chosen_model;
    if (select_series) {
      d.calibration = *select_series;
      d.calibration_fit = *d.train;
    } else {
      auto [fit_rows, held_rows] = sysid::SplitAtHoldout(*d.train, fit.selection->holdout_samples);
      d.calibration = std::move(held_rows);
      d.calibration_fit = std::move(fit_rows);
    }
  }
  cfg = fit.config;
  topt.epochs = fit.train.epochs;
  report["epoch_history"] = EpochHistoryToJson(fit.report);
  report["simulation"] = StagesToJson(fit.report.simulation);
  topt.deviation_ridge = fit.train.deviation_ridge;
  // The callbacks hold this function's locals; the options outlive it.
  topt.progress = nullptr;
  topt.simulation_progress = nullptr;
  return std::move(fit.model);
}

// Scores per output: blocks[k] goes to output k's `key`, under baselines/`where` unless empty.
void Put(std::vector<nlohmann::json>& per, const std::vector<nlohmann::json>& blocks,
         const std::string& where, const std::string& key) {
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    if (where.empty())
      per[k][key] = blocks[k];
    else
      per[k]["baselines"][where][key] = blocks[k];
  }
}

// Warnings only: the validation data informs the reader, never a choice.
void WarnWhereBaselinesWin(const sysid::RegressorSpec& spec, const std::vector<nlohmann::json>& per,
                           nlohmann::json& warnings) {
  const std::size_t n_outputs = spec.outputs.size();
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

// The readable form (docs/identifier.md §7.5) is a model too: scored beside the full one, its
// cost a FIT figure. None when it cannot be made (a warning says why).
std::optional<sysid::ReadableModel> ScoreReadable(const FitJobOptions& o,
                                                  const sysid::NarxModel& model, const JobData& d,
                                                  double sample_time_s,
                                                  std::vector<nlohmann::json>& per,
                                                  nlohmann::json& warnings) {
  const sysid::RegressorSpec& spec = model.spec();
  try {
    sysid::ReadableOptions ro;
    ro.criterion_horizon = o.horizon;
    sysid::ReadableModel readable = sysid::MakeReadable(model, *d.train, sample_time_s, ro);
    const sysid::NarxModel& rm = readable.model;
    const sysid::Predictor predict = [&rm](const Eigen::VectorXd& x) { return rm.Predict(x); };
    Put(per, Evaluate(spec, *d.train, predict, o.horizon), "readable", "train");
    if (d.validate)
      Put(per, Evaluate(spec, *d.validate, predict, o.horizon), "readable", "validate");
    return readable;
  } catch (const std::exception& e) {
    warnings.push_back(std::string("no readable form: ") + e.what());
    return std::nullopt;
  }
}

// The baselines fitted on --train (ARX, ARX with squared inputs, persistence) scored beside the
// model; then the tracking run and the predictions file, which show the model beside ARX.
void ScoreBaselines(const FitJobOptions& o, const sysid::NarxModel& model, JobData& d,
                    std::vector<nlohmann::json>& per, nlohmann::json& report) {
  const sysid::RegressorSpec& spec = model.spec();
  const auto arx = sysid::ArxModel::Fit(spec, *d.train);
  const sysid::Predictor arx_predict = [&arx](const Eigen::VectorXd& x) { return arx.Predict(x); };
  Put(per, Evaluate(spec, *d.train, arx_predict, o.horizon), "arx", "train");
  Put(per, EvaluatePersistence(spec, *d.train, o.horizon), "persistence", "train");
  // ARX with squared inputs: whether a static input nonlinearity explains the fuzzy model's
  // gain (only with inputs: without them it is ARX).
  std::optional<sysid::QuadraticArxModel> quadratic;
  if (!spec.inputs.empty() && spec.input_lags > 0)
    quadratic = sysid::QuadraticArxModel::Fit(spec, *d.train);
  const sysid::Predictor quadratic_predict = [&quadratic](const Eigen::VectorXd& x) {
    return quadratic->Predict(x);
  };
  if (quadratic)
    Put(per, Evaluate(spec, *d.train, quadratic_predict, o.horizon), "arx_squared_inputs", "train");
  if (d.validate) {
    Put(per, Evaluate(spec, *d.validate, arx_predict, o.horizon), "arx", "validate");
    if (quadratic)
      Put(per, Evaluate(spec, *d.validate, quadratic_predict, o.horizon), "arx_squared_inputs",
          "validate");
    Put(per, EvaluatePersistence(spec, *d.validate, o.horizon), "persistence", "validate");
    WarnWhereBaselinesWin(spec, per, d.warnings);
  }
  if (!o.track_csv.empty()) {
    const sysid::Series track = LoadSeries(o.track_csv, o, spec, nullptr, &d.warnings);
    report["track"] =
        Track(spec, track, model, arx, o.track_output, o.track_window, o.track_forgetting);
  }
  if (!o.predictions.empty()) {
    const sysid::Predictor predict = [&model](const Eigen::VectorXd& x) {
      return model.Predict(x);
    };
    std::vector<std::pair<std::string, const sysid::Series*>> sets{{"train", &*d.train}};
    if (d.validate) sets.emplace_back("validate", &*d.validate);
    WritePredictions(o.predictions, spec, sets, predict, arx_predict, o.horizon,
                     d.widths ? &*d.widths : nullptr);
    report["predictions_file"] = o.predictions;
  }
}

// The choices carried over to the online identifier: odonata-identifier --config takes this
// as it is (written by the configuration's one writer, identifier_config.hpp).
void WriteIdentifierConfig(const FitJobOptions& o, const sysid::NarxModel& model,
                           const sysid::Series& train) {
  identifier::IdentifierConfig c;
  c.spec = model.spec();
  // The learner's settings as chosen here, its refits choosing as this fit did: K steps ahead
  // with --horizon K.
  c.model = model.model(0).config();
  c.refit.horizon = o.horizon;
  c.ranges = o.ranges.empty() ? sysid::RangesFromSeries(c.spec, train) : ReadRanges(o.ranges);
  c.source = identifier::SampleSource::kSignals;
  // Whole or absent (a full disk must not leave an empty configuration and exit 0).
  io::WriteFileAtomically(o.save_config, identifier::IdentifierConfigToJson(c).dump(2) + "\n");
}

// Whether the training data holds anything to identify (sysid/model/excitation.hpp), for what
// this job will do with it: its warnings join the job's.
sysid::ExcitationReport CheckData(const FitJobOptions& o, const sysid::RegressorSpec& spec,
                                  const sysid::Series& train, JobData& d) {
  sysid::ExcitationNeeds needs;
  needs.horizon = o.horizon;
  const bool choosing =
      !o.refit.enabled() && o.select &&
      !(o.consequent_given && o.threshold_given && o.kappa_given && o.epochs_given);
  if (choosing && o.select_csv.empty()) needs.holdout_fraction = o.selection.holdout_fraction;
  sysid::ExcitationReport r = sysid::CheckExcitation(spec, train, needs, o.train_csv);
  for (const auto& w : r.warnings) d.warnings.push_back(w);
  return r;
}

nlohmann::json ExcitationToJson(const sysid::ExcitationReport& r) {
  nlohmann::json j;
  j["targets"] = r.targets;
  if (r.holdout_targets > 0) j["holdout_targets"] = r.holdout_targets;
  for (const auto& s : r.signals)
    j["signals"][s.name] = {{"role", s.output ? "output" : "input"},
                            {"min", s.min},
                            {"max", s.max},
                            {"std", s.std},
                            {"levels", s.levels}};
  return j;
}

}  // namespace

nlohmann::json RunFitJob(const FitJobOptions& o) {
  std::optional<sysid::NarxModel> model;
  const sysid::RegressorSpec spec = SpecFor(o, model);
  const std::size_t n_outputs = spec.outputs.size();
  nlohmann::json report;
  JobData d;
  if (!o.train_csv.empty()) d.train = LoadSeries(o.train_csv, o, spec, &d.files, &d.warnings);
  if (!o.validate_csv.empty())
    d.validate = LoadSeries(o.validate_csv, o, spec, &d.files, &d.warnings);
  if (!d.train && !model) throw std::runtime_error("nothing to do: give --train or --load-model");
  if (!o.track_csv.empty() && n_outputs > 1)
    throw std::runtime_error("--track follows one output; give one --output");
  if (d.train && !model) report["excitation"] = ExcitationToJson(CheckData(o, spec, *d.train, d));
  ProgressBar bar(o.progress);
  fuzzy::FuzzyModelConfig cfg = o.model;
  sysid::TrainOptions topt = o.train;
  std::optional<sysid::Scaling> declared;
  if (!model && !o.ranges.empty()) {
    declared = DeclaredScaling(o, spec);
    topt.fit_scaling = false;
  }
  const bool search = !model && !o.refit.enabled() && o.select &&
                      !(o.consequent_given && o.threshold_given && o.kappa_given && o.epochs_given);
  if (!o.save_ranges.empty() && d.train) {
    io::WriteFileAtomically(
        o.save_ranges, sysid::RangesToJson(sysid::RangesFromSeries(spec, *d.train)).dump(1) + "\n");
  }
  if (!search && o.simulation_given && o.train.refine_least_squares) topt.simulation = o.simulation;
  if (!model && o.refit.enabled()) {
    // The online identifier's learner, replayed: every row in order through the same class, with
    // its scheduled refits and the refit that closes learning (docs/identifier.md §6.3). With
    // --horizon, they choose by what is reported, as the identifier's refit_horizon.
    sysid::RefitSchedule refit = o.refit;
    refit.horizon = o.horizon;
    sysid::OnlineReplay replay = sysid::LearnOnline(sysid::NarxModel(spec, cfg), refit, *d.train,
                                                    declared, !o.replay_unfrozen);
    report["refits"] = RefitsToJson(replay, spec);
    model.emplace(std::move(replay.model));
  } else if (!model) {
    model.emplace(TrainOffline(o, spec, search, declared, cfg, topt, d, bar, report));
  }
  bar.Finish();
  PutModelSettings(o, *model, topt, report);
  // Scores per output: the first output's at the top level (as with one output), every output's
  // under per_output when there are several.
  std::vector<nlohmann::json> per(n_outputs, nlohmann::json::object());
  const sysid::Predictor predict = [&model](const Eigen::VectorXd& x) { return model->Predict(x); };
  if (d.train) Put(per, Evaluate(spec, *d.train, predict, o.horizon), "", "train");
  if (d.calibration_model) {
    const sysid::Predictor candidate = [&d](const Eigen::VectorXd& x) {
      return d.calibration_model->Predict(x);
    };
    // Widths where the candidate's rules fitted loosely or saw little (local_spread.hpp).
    const LocalSpread spread = LocalSpread::Fit(*d.calibration_model, *d.calibration_fit);
    d.widths =
        CalibrateIntervals(spec, *d.calibration, candidate, o.horizon, o.interval_level, spread);
  }
  if (d.validate) {
    Put(per, Evaluate(spec, *d.validate, predict, o.horizon, d.widths ? &*d.widths : nullptr), "",
        "validate");
  }
  // Time constants in seconds when the training data's rate is known (a time column or a ULog).
  double sample_time_s = 0;
  if (!o.train_csv.empty() && d.files.contains(o.train_csv) &&
      d.files[o.train_csv].contains("rate_hz"))
    sample_time_s = 1.0 / d.files[o.train_csv]["rate_hz"].get<double>();
  std::optional<sysid::ReadableModel> readable;
  if (d.train) {
    readable = ScoreReadable(o, *model, d, sample_time_s, per, d.warnings);
    ScoreBaselines(o, *model, d, per, report);
  }
  for (std::size_t k = 0; k < n_outputs; ++k) {
    PutRuleDescriptions(*model, static_cast<int>(k), readable ? &*readable : nullptr, sample_time_s,
                        per[k]);
    if (d.train)
      PutUncertainty(*model, static_cast<int>(k), readable ? &*readable : nullptr, *d.train,
                     sample_time_s, per[k]);
  }
  // The first output at the top level, as a one-output report always had it.
  for (const char* key :
       {"train", "validate", "baselines", "rule_text", "local_models", "readable"})
    if (per[0].contains(key)) report[key] = per[0][key];
  report["outputs"] = spec.outputs;
  if (n_outputs > 1) {
    for (std::size_t k = 0; k < n_outputs; ++k) report["per_output"][spec.outputs[k]] = per[k];
  }
  if (d.validate || d.train) {
    report["verdict"] = Verdict(report, *model, d.validate ? *d.validate : *d.train);
    report["verdict"]["rules"] = report["rules"];
  }
  report["warnings"] = d.warnings;
  report["data"] = d.files;
  if (!o.save_config.empty() && d.train) {
    WriteIdentifierConfig(o, *model, *d.train);
    report["config_file"] = o.save_config;
  }
  if (!o.save_model.empty()) {
    // Each rule's parameter covariance from the training data, for odonata-export's local models.
    const nlohmann::json covariance =
        d.train ? sysid::LocalCovariancesToJson(*model, *d.train, sample_time_s) : nlohmann::json();
    model->Save(o.save_model, sample_time_s, &covariance);
    report["model_file"] = o.save_model;
  }
  if (!o.plot_dir.empty() && (d.validate || d.train)) {
    WritePlotData(o.plot_dir, *model, readable ? &*readable : nullptr,
                  d.validate ? *d.validate : *d.train, sample_time_s, report);
    try {
      report["plots"] = DrawPlots(o.plot_dir);
    } catch (const std::exception& e) {
      report["warnings"].push_back(std::string("no pictures: ") + e.what());
    }
  }
  return report;
}

}  // namespace odonata::fit

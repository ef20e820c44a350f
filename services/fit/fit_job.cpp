#include "fit_job.hpp"

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
#include "sysid/arx_model.hpp"
#include "sysid/free_run.hpp"
#include "sysid/local_dynamics.hpp"
#include "sysid/offline_fit.hpp"
#include "sysid/online_identifier.hpp"
#include "sysid/quadratic_arx_model.hpp"
#include "sysid/readable_model.hpp"
#include "sysid/rule_listing.hpp"
#include "sysid/signal_ranges.hpp"

#include <fstream>

namespace odonata::fit {
namespace {

// One data file as a series of the spec's signals, under the rules for real logs; what was
// bridged or cut goes into `data` (and a warning).
sysid::Series LoadSeries(const std::string& path, const FitJobOptions& o,
                         const sysid::RegressorSpec& spec, nlohmann::json* data,
                         nlohmann::json* warnings) {
  // A CSV as it is, or a PX4 ULog's signals resampled onto one grid (--rate) with a t_s column.
  records::RecordOptions ro;
  ro.csv_format = o.csv_format;
  ro.signals = spec.outputs;
  ro.signals.insert(ro.signals.end(), spec.inputs.begin(), spec.inputs.end());
  ro.rate_hz = o.rate_hz;
  ro.max_gap = o.max_gap;
  records::Record record = records::ReadRecord(path, ro);
  const io::CsvTable& table = record.table;
  sysid::SeriesOptions so;
  so.outputs = spec.outputs;
  so.inputs = spec.inputs;
  so.time_column = o.time_column.empty() ? record.time_column : o.time_column;
  so.rate_hz = o.rate_hz > 0 ? o.rate_hz : record.rate_hz;
  so.max_gap = o.max_gap;
  // Every segment kept has at least two targets, so a file that passes can be scored.
  so.min_segment = spec.first_target() + 2;
  sysid::SeriesReport r;
  sysid::Series s = sysid::SeriesFromTable(table, so, &r);
  nlohmann::json d = {{"file", path},
                      {"rows", r.rows},
                      {"samples", r.samples},
                      {"segments", r.segments},
                      {"bridged", r.bridged},
                      {"missing", r.missing},
                      {"dropped_segments", r.dropped_segments}};
  if (!so.time_column.empty()) d["rate_hz"] = r.rate_hz;
  if (data) (*data)[path] = d;
  if (warnings)
    for (const auto& w : record.warnings) warnings->push_back(w);
  if (warnings && (r.bridged > 0 || r.missing > 0 || r.segments > 1)) {
    warnings->push_back(path + ": " + std::to_string(r.bridged) + " missing values bridged, " +
                        std::to_string(r.missing) + " samples dropped in longer gaps, " +
                        std::to_string(r.segments) + " segment(s) used");
  }
  return s;
}

/// Scores a predictor on a series in both modes, one block per output.
std::vector<nlohmann::json> Evaluate(const sysid::RegressorSpec& spec, const sysid::Series& s,
                                     const sysid::Predictor& predict, int horizon) {
  const Eigen::MatrixXd y = sysid::Targets(spec, s);
  const Eigen::MatrixXd one = sysid::PredictOneStep(spec, s, predict);
  bool diverged = false;
  Eigen::MatrixXd sim;
  if (spec.output_lags > 0) sim = sysid::SimulateFreeRun(spec, s, predict, &diverged);
  const bool ahead = horizon > 1 && spec.output_lags > 0;
  bool ahead_diverged = false;
  Eigen::MatrixXd k_step;
  if (ahead) k_step = sysid::PredictAhead(spec, s, predict, horizon, &ahead_diverged);
  std::vector<nlohmann::json> out;
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    nlohmann::json j;
    j["one_step"] = metrics::AccuracyToJson(metrics::Score(y.col(o), one.col(o)));
    if (spec.output_lags > 0) {
      j["free_run"] = metrics::AccuracyToJson(metrics::Score(y.col(o), sim.col(o)));
      if (diverged) j["free_run"]["diverged"] = true;
    }
    if (ahead) {
      j["k_step"] = metrics::AccuracyToJson(metrics::Score(y.col(o), k_step.col(o)));
      j["k_step"]["horizon"] = horizon;
      if (ahead_diverged) j["k_step"]["diverged"] = true;
    }
    out.push_back(j);
  }
  return out;
}

/// Persistence ŷ(t) = y(t−1) one step ahead; free run holds the last measured value before each
/// segment's first target. One block per output.
std::vector<nlohmann::json> EvaluatePersistence(const sysid::RegressorSpec& spec,
                                                const sysid::Series& s) {
  const auto targets = sysid::TargetRows(spec, s);
  const auto rows = static_cast<Eigen::Index>(targets.size());
  const Eigen::MatrixXd y = sysid::Targets(spec, s);
  Eigen::MatrixXd one(rows, y.cols()), held(rows, y.cols());
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index t = targets[static_cast<std::size_t>(r)];
    const bool first = r == 0 || targets[static_cast<std::size_t>(r) - 1] != t - 1;
    one.row(r) = s.outputs.row(std::max<Eigen::Index>(t - 1, 0));
    if (first)
      held.row(r) = s.outputs.row(std::max<Eigen::Index>(t - 1, 0));
    else
      held.row(r) = held.row(r - 1);
  }
  std::vector<nlohmann::json> out;
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    nlohmann::json j;
    j["one_step"] = metrics::AccuracyToJson(metrics::Score(y.col(o), one.col(o)));
    if (spec.output_lags > 0)
      j["free_run"] = metrics::AccuracyToJson(metrics::Score(y.col(o), held.col(o)));
    out.push_back(j);
  }
  return out;
}

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
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{"consequent", fuzzy::ToString(c.consequent)},
          {"linear", c.linear},
          {"simulation", StagesToJson(c.simulation)},
          {"entropy_threshold", c.threshold},
          {"kappa", c.kappa},
          {"deviation_ridge", c.deviation_ridge},
          {"epochs", c.epochs},
          {"rules", c.rules},
          {"at_cap", c.at_cap},
          {"holdout_one_step_ndei", num(c.holdout_one_step_ndei)},
          {"holdout_free_run_ndei", num(c.holdout_free_run_ndei)},
          {"holdout_ahead_ndei", num(c.holdout_ahead_ndei)},
          {"score", num(c.score)},
          {"rest_deviation", num(c.rest_deviation)},
          {"restless", c.restless},
          {"one_step_lost", c.one_step_lost}};
}

/// Writes sample-by-sample predictions of the model and of ARX, both modes, for each data set.
/// One output keeps the plain column names; several get one set of columns per output (_NAME).
/// With a horizon K (> 1), fuzzy_k_step and arx_k_step follow: each a free run of K samples from
/// the measured outputs before it.
void WritePredictions(const std::string& path, const sysid::RegressorSpec& spec,
                      const std::vector<std::pair<std::string, const sysid::Series*>>& sets,
                      const sysid::Predictor& fuzzy, const sysid::Predictor& arx, int horizon) {
  const auto no = spec.outputs.size();
  const bool ahead = horizon > 1 && spec.output_lags > 0;
  std::vector<std::string> header{"set", "sample"};
  for (const auto& name : spec.outputs) {
    const std::string sfx = no > 1 ? "_" + name : "";
    for (const char* c :
         {"measured", "fuzzy_one_step", "fuzzy_free_run", "arx_one_step", "arx_free_run"})
      header.push_back(c + sfx);
    if (ahead)
      for (const char* c : {"fuzzy_k_step", "arx_k_step"}) header.push_back(c + sfx);
  }
  io::CsvWriter out(path, header);
  double set_index = 0;
  for (const auto& [name, s] : sets) {
    const auto targets = sysid::TargetRows(spec, *s);
    const Eigen::MatrixXd f1 = sysid::PredictOneStep(spec, *s, fuzzy);
    const Eigen::MatrixXd a1 = sysid::PredictOneStep(spec, *s, arx);
    const bool lags = spec.output_lags > 0;
    const Eigen::MatrixXd fr = lags ? sysid::SimulateFreeRun(spec, *s, fuzzy) : f1;
    const Eigen::MatrixXd ar = lags ? sysid::SimulateFreeRun(spec, *s, arx) : a1;
    const Eigen::MatrixXd fk = ahead ? sysid::PredictAhead(spec, *s, fuzzy, horizon) : f1;
    const Eigen::MatrixXd ak = ahead ? sysid::PredictAhead(spec, *s, arx, horizon) : a1;
    for (Eigen::Index r = 0; r < f1.rows(); ++r) {
      const Eigen::Index t = targets[static_cast<std::size_t>(r)];
      std::vector<double> row{set_index, double(t)};
      for (Eigen::Index o = 0; o < f1.cols(); ++o) {
        for (const double v : {s->outputs(t, o), f1(r, o), fr(r, o), a1(r, o), ar(r, o)})
          row.push_back(v);
        if (ahead) {
          row.push_back(fk(r, o));
          row.push_back(ak(r, o));
        }
      }
      out.WriteRow(row);
    }
    ++set_index;
  }
  out.Close();
}

/// The tracking run of FitJobOptions::track_csv: one-step predictions of the model learning on
/// (online), of a frozen copy and of ARX, each with its accuracy alarm.
nlohmann::json Track(const sysid::RegressorSpec& spec, const sysid::Series& s,
                     const sysid::NarxModel& trained, const sysid::ArxModel& arx,
                     const std::string& output, int window, double forgetting) {
  sysid::NarxModel online = trained;
  if (forgetting > 0.0) {
    for (int o = 0; o < online.outputs(); ++o) online.mutable_model(o).set_forgetting(forgetting);
  }
  const sysid::NarxModel& frozen = trained;
  const sysid::RegressionData d = sysid::BuildRegression(spec, s);
  const char* names[] = {"online", "frozen", "arx"};
  metrics::AccuracyAlarmOptions alarm_options;
  alarm_options.window = static_cast<std::size_t>(window);
  metrics::AccuracyAlarm alarms[3] = {metrics::AccuracyAlarm(alarm_options),
                                      metrics::AccuracyAlarm(alarm_options),
                                      metrics::AccuracyAlarm(alarm_options)};
  nlohmann::json events[3] = {nlohmann::json::array(), nlohmann::json::array(),
                              nlohmann::json::array()};
  std::optional<io::CsvWriter> out;
  if (!output.empty())
    out.emplace(output, std::vector<std::string>{"sample", "measured", "online", "frozen", "arx",
                                                 "online_window_fit", "frozen_window_fit",
                                                 "arx_window_fit"});
  const auto targets = sysid::TargetRows(spec, s);
  Eigen::MatrixXd yhat(d.x.rows(), 3);
  for (Eigen::Index r = 0; r < d.x.rows(); ++r) {
    const Eigen::VectorXd x = d.x.row(r).transpose();
    const double y = d.y(r, 0);
    const double p_frozen = frozen.Predict(x)(0);
    const double p_arx = arx.Predict(x)(0);
    // The prediction before learning from y, as the online identifier reports it: Learn()'s own
    // prediction already includes a rule created for this very sample.
    const double p_online = online.Predict(x)(0);
    online.Learn(x, d.y.row(r).transpose());
    const double p[3] = {p_online, p_frozen, p_arx};
    const auto t = targets[static_cast<std::size_t>(r)];
    std::vector<double> row = {double(t), y, p_online, p_frozen, p_arx, 0, 0, 0};
    for (int m = 0; m < 3; ++m) {
      yhat(r, m) = p[m];
      const auto e = alarms[m].Push(long(t), y, p[m]);
      row[static_cast<std::size_t>(5 + m)] = alarms[m].tracking_fit();
      if (e) {
        events[m].push_back(
            {{"kind", e->kind == metrics::AccuracyEvent::Kind::kAlarm ? "alarm" : "recovered"},
             {"sample", e->sample},
             {"window_fit", e->window_fit},
             {"reference_fit", e->reference_fit}});
      }
    }
    if (out) out->WriteRow(row);
  }
  if (out) out->Close();
  nlohmann::json j;
  j["samples"] = d.x.rows();
  j["rules_before"] = trained.total_rules();
  j["rules_after"] = online.total_rules();
  for (int m = 0; m < 3; ++m) {
    j[names[m]]["events"] = events[m];
    j[names[m]]["one_step"] = metrics::AccuracyToJson(metrics::Score(d.y.col(0), yhat.col(m)));
  }
  int pruned = 0;
  for (int o = 0; o < online.outputs(); ++o) pruned += int(online.model(o).rules_pruned());
  j["rules_pruned"] = pruned;
  if (!output.empty()) j["file"] = output;
  return j;
}

}  // namespace

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
    c["consequent"] = fuzzy::ToString(fm0.consequent);
    c["entropy_threshold"] = fm0.entropy.threshold;
    c["kappa"] = fm0.entropy.kappa;
    c["max_rules"] = fm0.entropy.max_rules;
    c["sigma_init"] = fm0.entropy.sigma_init;
    c["sigma_min"] = fm0.entropy.sigma_min;
    c["sigma_max"] = fm0.entropy.sigma_max;
    c["forgetting"] = fm0.forgetting;
    c["prune_utility"] = fm0.entropy.prune_utility;
    c["prune_min_age"] = fm0.entropy.prune_min_age;
    nlohmann::json ranges;
    if (!o.ranges.empty()) {
      std::ifstream in(o.ranges);
      in >> ranges;
    } else {
      ranges = sysid::RangesToJson(sysid::RangesFromSeries(spec, *train));
    }
    c["ranges"] = ranges;
    const sysid::RefitSchedule refit = sysid::RefitSchedule::IdentifierDefault();
    c["refit_first"] = refit.first;
    c["refit_every"] = refit.every;
    c["refit_buffer"] = refit.buffer;
    c["refit_history"] = refit.history;
    c["refit_at_freeze"] = refit.at_freeze;
    // Its refits choose as this fit did: K steps ahead with --horizon K.
    c["refit_horizon"] = o.horizon;
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
  return report;
}

std::string FormatReport(const nlohmann::json& r, RulesShown rules_shown) {
  std::ostringstream out;
  char line[256];
  out << "odonata-fit: " << r["target"].get<std::string>() << " from";
  for (const auto& name : r["regressors"]) out << ' ' << name.get<std::string>();
  out << "\n  " << r["rules"].get<int>() << " rules (" << r["consequent"].get<std::string>()
      << " consequents), entropy threshold H = " << r["entropy_threshold"].get<double>()
      << ", kappa " << r["kappa"].get<double>() << ", " << r["epochs"].get<int>() << " epochs, cap "
      << r["max_rules"].get<int>() << "\n";
  if (r.contains("refits")) {
    const auto& f = r["refits"];
    out << "  the online identifier replayed: " << f["samples_learned"].get<long>()
        << " samples learned, " << f["landed"].get<long>() << " refits landed ("
        << f["failed"].get<long>() << " failed, " << f["incumbents_kept"].get<long>()
        << " kept the last refit's model, " << f["steady_state_refused"].get<long>()
        << " steady-state models refused by their checks, " << f["linear_landed"].get<long>()
        << " landed the linear model, which won on the samples since they began)\n";
  }
  if (r.contains("selection")) {
    const auto& sel = r["selection"];
    const std::string on = sel.value("scored_on", std::string("training hold-out"));
    out << "\n  model selection on " << sel["holdout_samples"].get<long>() << " samples of "
        << (on == "training hold-out" ? std::string("the training file's end") : on) << " ("
        << sel["criterion"].get<std::string>() << " NDEI; fewest rules within "
        << 100 * sel["relative_tolerance"].get<double>() << " % or "
        << sel["absolute_tolerance"].get<double>()
        << " of the best):\n      consequent  H        kappa  epochs  rules  one-step NDEI  "
           "free-run NDEI";
    // Scored K steps ahead, the score itself is a column too.
    const int ahead = sel["criterion"] == "k_step" ? sel["criterion_horizon"].get<int>() : 0;
    if (ahead > 0) {
      const std::string head = std::to_string(ahead) + "-step NDEI";
      out << std::string(15 - std::min<std::size_t>(head.size(), 13), ' ') << head;
    }
    out << "  ridge\n";
    if (sel.value("searched_rows", 0L) < sel.value("training_rows", 0L))
      out << "    (searched on " << sel["searched_rows"].get<long>() << " of the "
          << sel["training_rows"].get<long>()
          << " training rows, in blocks spread over the file; --search-rows)\n";
    std::size_t k = 0;
    auto num = [](const nlohmann::json& v) { return v.is_null() ? NAN : v.get<double>(); };
    for (const auto& c : sel["candidates"]) {
      const bool chosen = k == sel["chosen_index"].get<std::size_t>();
      const bool best = k == sel["best_index"].get<std::size_t>();
      const bool linear = c.value("linear", false);
      const bool from_linear =
          !c["simulation"].empty() && c["simulation"].front().value("from_linear", false);
      char ahead_cell[32] = "";
      if (ahead > 0)
        std::snprintf(ahead_cell, sizeof ahead_cell, "  %13.4g",
                      num(c.value("holdout_ahead_ndei", nlohmann::json())));
      std::snprintf(line, sizeof line,
                    "    %s %-10s %-8.4g %5.2g  %6d  %5d  %13.4g  %13.4g%s  %5.2g%s\n",
                    chosen ? "*" : " ", linear ? "ARX" : c["consequent"].get<std::string>().c_str(),
                    c["entropy_threshold"].get<double>(), c["kappa"].get<double>(),
                    c["epochs"].get<int>(), c["rules"].get<int>(), num(c["holdout_one_step_ndei"]),
                    num(c["holdout_free_run_ndei"]), ahead_cell, c.value("deviation_ridge", 0.0),
                    c.value("restless", false)        ? "  (oscillates at rest)"
                    : c.value("one_step_lost", false) ? "  (worse than ARX one step ahead)"
                    : best && from_linear             ? "  (best; from ARX)"
                    : best                            ? "  (best)"
                    : from_linear                     ? "  (from ARX)"
                                                      : "");
      out << line;
      ++k;
    }
    if (sel.contains("linear_fit_check")) {
      const auto& oc = sel["linear_fit_check"];
      std::snprintf(line, sizeof line,
                    "    the linear model's fits, %d folds, mean NDEI: output error %.4g, one "
                    "step %.4g: %s kept\n",
                    oc["folds"].get<int>(), num(oc["output_error_ndei"]), num(oc["one_step_ndei"]),
                    oc["output_error_kept"].get<bool>() ? "output error" : "one step");
      out << line;
    }
    if (sel.contains("linear_check")) {
      const nlohmann::json checks = sel.contains("linear_checks")
                                        ? sel["linear_checks"]
                                        : nlohmann::json::array({sel["linear_check"]});
      for (const auto& lc : checks) {
        const bool lost = lc["linear_chosen"].get<bool>();
        const bool last = &lc == &checks.back();
        std::snprintf(
            line, sizeof line,
            "    blocked cross-validation, %d folds, mean NDEI: fuzzy %.4g (%d rules), ARX %.4g, "
            "margin needed %.2g: %s\n",
            lc["folds"].get<int>(), num(lc["fuzzy_ndei"]),
            lc.contains("candidate_index")
                ? sel["candidates"][lc["candidate_index"].get<std::size_t>()].value("rules", 0)
                : 0,
            num(lc["linear_ndei"]), lc.value("margin", 0.0),
            !lost  ? "fuzzy kept"
            : last ? "ARX kept"
                   : "lost, the next by hold-out is tried");
        out << line;
      }
    }
  }
  auto row = [&](const char* data, const char* model, const nlohmann::json& block) {
    for (const char* mode : {"one_step", "free_run", "k_step"}) {
      if (!block.contains(mode)) continue;
      const auto& a = block[mode];
      auto get = [&](const char* k) { return a[k].is_null() ? NAN : a[k].get<double>(); };
      std::snprintf(line, sizeof line, "  %-10s %-10s %-11s %8.2f  %8.2f  %10.4g\n", data, mode,
                    model, get("fit"), get("vaf"), get("rmse"));
      out << line;
    }
  };
  // One table (and rule list) per output: the top level holds the first, per_output all.
  const auto table = [&](const nlohmann::json& b) {
    out << "\n  data       mode       model         FIT %     VAF %        RMSE\n";
    for (const char* data : {"train", "validate"}) {
      if (!b.contains(data)) continue;
      row(data, "fuzzy", b[data]);
      if (!b.contains("baselines")) continue;
      const auto& base = b["baselines"];
      if (base.contains("arx") && base["arx"].contains(data)) row(data, "ARX", base["arx"][data]);
      if (base.contains("arx_squared_inputs") && base["arx_squared_inputs"].contains(data))
        row(data, "ARX+u^2", base["arx_squared_inputs"][data]);
      if (base.contains("persistence") && base["persistence"].contains(data))
        row(data, "persistence", base["persistence"][data]);
      if (base.contains("readable") && base["readable"].contains(data))
        row(data, "readable", base["readable"][data]);
    }
  };
  const auto rules = [&](const nlohmann::json& b) {
    // The readable form by default (the full one when there is none), the full one on request.
    const bool readable = rules_shown == RulesShown::kReadable && b.contains("readable");
    if (rules_shown == RulesShown::kNone || (!readable && !b.contains("rule_text"))) return;
    if (readable) {
      const auto& rd = b["readable"];
      out << "\n  rules, readable form (" << rd["rules"].get<int>() << " of "
          << b["rules"].get<int>() << "; --full-rules for every rule):\n";
      for (const auto& s : rd["text"]) out << "    " << s.get<std::string>() << "\n";
      return;
    }
    out << "\n  rules:\n";
    int k = 1;
    for (const auto& s : b["rule_text"]) out << "  " << k++ << ". " << s.get<std::string>() << "\n";
  };
  if (r.contains("per_output")) {
    for (const auto& [name, b] : r["per_output"].items()) {
      out << "\n  " << b["target"].get<std::string>() << ": " << b["rules"].get<int>()
          << " rules\n";
      table(b);
      rules(b);
    }
  } else {
    table(r);
    rules(r);
  }
  if (r.contains("warnings")) {
    for (const auto& w : r["warnings"]) out << "\n  warning: " << w.get<std::string>();
    if (!r["warnings"].empty()) out << "\n";
  }
  if (r.contains("predictions_file"))
    out << "\n  predictions written to " << r["predictions_file"].get<std::string>() << "\n";
  if (r.contains("model_file"))
    out << "\n  model saved to " << r["model_file"].get<std::string>() << "\n";
  return out.str();
}

}  // namespace odonata::fit

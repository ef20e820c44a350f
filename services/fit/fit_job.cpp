#include "fit_job.hpp"

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
#include "sysid/arx_model.hpp"
#include "sysid/free_run.hpp"
#include "sysid/quadratic_arx_model.hpp"
#include "sysid/rule_listing.hpp"
#include "sysid/signal_ranges.hpp"

#include <fstream>

namespace odonata::fit {
namespace {

sysid::Series LoadSeries(const std::string& path, const std::string& output,
                         const std::vector<std::string>& inputs, const sysid::RegressorSpec& spec) {
  const io::CsvTable table = io::CsvTable::Read(path);
  sysid::Series s;
  const auto rows = static_cast<Eigen::Index>(table.rows());
  s.outputs.resize(rows, 1);
  const auto& y = table.Column(output);
  for (Eigen::Index r = 0; r < rows; ++r) s.outputs(r, 0) = y[static_cast<std::size_t>(r)];
  s.inputs.resize(rows, static_cast<Eigen::Index>(inputs.size()));
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    const auto& u = table.Column(inputs[i]);
    for (Eigen::Index r = 0; r < rows; ++r)
      s.inputs(r, static_cast<Eigen::Index>(i)) = u[static_cast<std::size_t>(r)];
  }
  const int need = spec.first_target() + 2;
  if (rows < need) {
    throw std::runtime_error(path + ": " + std::to_string(rows) +
                             " data rows, but the lags (ny=" + std::to_string(spec.output_lags) +
                             ", nu=" + std::to_string(spec.input_lags) +
                             ", delay=" + std::to_string(spec.delay) + ") need at least " +
                             std::to_string(need));
  }
  return s;
}

/// Scores a predictor on a series in both modes.
nlohmann::json Evaluate(const sysid::RegressorSpec& spec, const sysid::Series& s,
                        const sysid::Predictor& predict) {
  const Eigen::Index t0 = spec.first_target();
  const Eigen::VectorXd y = s.outputs.col(0).tail(s.samples() - t0);
  nlohmann::json j;
  j["one_step"] =
      metrics::AccuracyToJson(metrics::Score(y, sysid::PredictOneStep(spec, s, predict).col(0)));
  if (spec.output_lags > 0) {
    bool diverged = false;
    const Eigen::MatrixXd sim = sysid::SimulateFreeRun(spec, s, predict, &diverged);
    j["free_run"] = metrics::AccuracyToJson(metrics::Score(y, sim.col(0)));
    if (diverged) j["free_run"]["diverged"] = true;
  }
  return j;
}

/// Persistence ŷ(t) = y(t−1) one step ahead; free run holds the last measured initial value.
nlohmann::json EvaluatePersistence(const sysid::RegressorSpec& spec, const sysid::Series& s) {
  const Eigen::Index t0 = std::max<Eigen::Index>(1, spec.first_target());
  const Eigen::Index rows = s.samples() - spec.first_target();
  const Eigen::VectorXd y = s.outputs.col(0).tail(rows);
  Eigen::VectorXd one(rows), held(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index t = spec.first_target() + r;
    one(r) = s.outputs(std::max<Eigen::Index>(t - 1, 0), 0);
    held(r) = s.outputs(t0 - 1, 0);
  }
  nlohmann::json j;
  j["one_step"] = metrics::AccuracyToJson(metrics::Score(y, one));
  if (spec.output_lags > 0) j["free_run"] = metrics::AccuracyToJson(metrics::Score(y, held));
  return j;
}

nlohmann::json CandidateToJson(const sysid::Candidate& c) {
  auto num = [](double v) {
    return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
  };
  return {{"consequent", fuzzy::ToString(c.consequent)},
          {"entropy_threshold", c.threshold},
          {"kappa", c.kappa},
          {"epochs", c.epochs},
          {"rules", c.rules},
          {"at_cap", c.at_cap},
          {"holdout_one_step_ndei", num(c.holdout_one_step_ndei)},
          {"holdout_free_run_ndei", num(c.holdout_free_run_ndei)},
          {"score", num(c.score)}};
}

/// Writes sample-by-sample predictions of the model and of ARX, both modes, for each data set.
void WritePredictions(const std::string& path, const sysid::RegressorSpec& spec,
                      const std::vector<std::pair<std::string, const sysid::Series*>>& sets,
                      const sysid::Predictor& fuzzy, const sysid::Predictor& arx) {
  io::CsvWriter out(path, {"set", "sample", "measured", "fuzzy_one_step", "fuzzy_free_run",
                           "arx_one_step", "arx_free_run"});
  double set_index = 0;
  for (const auto& [name, s] : sets) {
    const Eigen::Index t0 = spec.first_target();
    const Eigen::MatrixXd f1 = sysid::PredictOneStep(spec, *s, fuzzy);
    const Eigen::MatrixXd a1 = sysid::PredictOneStep(spec, *s, arx);
    const bool lags = spec.output_lags > 0;
    const Eigen::MatrixXd fr = lags ? sysid::SimulateFreeRun(spec, *s, fuzzy) : f1;
    const Eigen::MatrixXd ar = lags ? sysid::SimulateFreeRun(spec, *s, arx) : a1;
    for (Eigen::Index r = 0; r < f1.rows(); ++r) {
      out.WriteRow({set_index, double(t0 + r), s->outputs(t0 + r, 0), f1(r, 0), fr(r, 0), a1(r, 0),
                    ar(r, 0)});
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
  const Eigen::Index t0 = spec.first_target();
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
    std::vector<double> row = {double(t0 + r), y, p_online, p_frozen, p_arx, 0, 0, 0};
    for (int m = 0; m < 3; ++m) {
      yhat(r, m) = p[m];
      const auto e = alarms[m].Push(long(t0 + r), y, p[m]);
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
    spec.outputs = {o.output};
    spec.inputs = o.inputs;
    const std::string problems = spec.Problems();
    if (!problems.empty()) throw std::runtime_error("invalid model structure: " + problems);
    const std::string config_problems = o.model.Problems();
    if (!config_problems.empty()) throw std::runtime_error(config_problems);
  }
  const std::string output = spec.outputs.at(0);
  std::optional<sysid::Series> train, validate;
  if (!o.train_csv.empty()) train = LoadSeries(o.train_csv, output, spec.inputs, spec);
  if (!o.validate_csv.empty()) validate = LoadSeries(o.validate_csv, output, spec.inputs, spec);
  if (!train && !model) throw std::runtime_error("nothing to do: give --train or --load-model");

  nlohmann::json report;
  nlohmann::json warnings = nlohmann::json::array();
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
  const bool search = !model && o.select &&
                      !(o.consequent_given && o.threshold_given && o.kappa_given && o.epochs_given);
  if (search) {
    sysid::SelectionOptions so = o.selection;
    if (o.consequent_given) so.consequents = {cfg.consequent};
    if (o.threshold_given) so.thresholds = {cfg.entropy.threshold};
    if (o.kappa_given) so.kappas = {cfg.entropy.kappa};
    if (o.epochs_given) {
      so.max_epochs = o.train.epochs;
      so.patience = 0;
    }
    // Candidates learn with the declared scaling when there is one, as the final model will.
    so.scaling = declared;
    std::optional<sysid::Series> select_series;
    if (!o.select_csv.empty()) select_series = LoadSeries(o.select_csv, output, spec.inputs, spec);
    const auto sel = sysid::SelectModel(
        spec, cfg, topt, *train, so,
        [&bar](const sysid::Candidate& c, std::size_t k, std::size_t n) {
          char label[96];
          std::snprintf(label, sizeof label, "selecting %s H=%.3g k=%.2g: %d rules",
                        fuzzy::ToString(c.consequent), c.threshold, c.kappa, c.rules);
          bar.Update(label, double(k) / double(n));
        },
        select_series ? &*select_series : nullptr);
    nlohmann::json cands = nlohmann::json::array();
    for (const auto& c : sel.candidates) cands.push_back(CandidateToJson(c));
    report["selection"] = {{"criterion", sel.free_run_criterion ? "free_run" : "one_step"},
                           {"scored_on", o.select_csv.empty() ? "training hold-out" : o.select_csv},
                           {"relative_tolerance", so.relative_tolerance},
                           {"absolute_tolerance", so.absolute_tolerance},
                           {"fit_samples", sel.fit_samples},
                           {"holdout_samples", sel.holdout_samples},
                           {"candidates", cands},
                           {"best_index", sel.best},
                           {"chosen_index", sel.chosen}};
    for (const auto& w : sel.warnings) warnings.push_back(w);
    const auto& c = sel.candidates[sel.chosen];
    cfg.consequent = c.consequent;
    cfg.entropy.threshold = c.threshold;
    cfg.entropy.kappa = c.kappa;
    if (!o.epochs_given) topt.epochs = std::max(1, c.epochs);
  }
  if (!o.save_ranges.empty() && train) {
    std::ofstream out(o.save_ranges);
    out << sysid::RangesToJson(sysid::RangesFromSeries(spec, *train)).dump(1) << "\n";
    if (!out) throw std::runtime_error(o.save_ranges + ": cannot write");
  }
  if (!model) {
    // The chosen settings, refitted on the whole training file (the hold-out included).
    model.emplace(spec, cfg);
    if (declared) model->SetScaling(*declared);
    topt.progress = [&bar, &topt](int epoch, long sample, long total) {
      bar.Update("epoch " + std::to_string(epoch + 1) + "/" + std::to_string(topt.epochs),
                 (epoch + double(sample) / double(total)) / topt.epochs);
    };
    const sysid::TrainReport tr = model->Train(*train, topt);
    nlohmann::json hist = nlohmann::json::array();
    for (const auto& e : tr.epochs)
      hist.push_back({{"epoch", e.epoch},
                      {"accepted", e.accepted},
                      {"train_fit", e.train_fit},
                      {"rules", e.rules}});
    report["epoch_history"] = hist;
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
  report["seed"] = o.seed;
  if (train) report["train"] = Evaluate(spec, *train, predict);
  if (validate) report["validate"] = Evaluate(spec, *validate, predict);
  if (train) {
    const auto arx = sysid::ArxModel::Fit(spec, *train);
    const sysid::Predictor arx_predict = [&arx](const Eigen::VectorXd& x) {
      return arx.Predict(x);
    };
    report["baselines"]["arx"]["train"] = Evaluate(spec, *train, arx_predict);
    report["baselines"]["persistence"]["train"] = EvaluatePersistence(spec, *train);
    // ARX with squared inputs: whether a static input nonlinearity explains the fuzzy model's
    // gain (only with inputs: without them it is ARX).
    std::optional<sysid::QuadraticArxModel> quadratic;
    if (!spec.inputs.empty() && spec.input_lags > 0) {
      quadratic = sysid::QuadraticArxModel::Fit(spec, *train);
    }
    const sysid::Predictor quadratic_predict = [&quadratic](const Eigen::VectorXd& x) {
      return quadratic->Predict(x);
    };
    if (quadratic) {
      report["baselines"]["arx_squared_inputs"]["train"] =
          Evaluate(spec, *train, quadratic_predict);
    }
    if (validate) {
      report["baselines"]["arx"]["validate"] = Evaluate(spec, *validate, arx_predict);
      if (quadratic) {
        report["baselines"]["arx_squared_inputs"]["validate"] =
            Evaluate(spec, *validate, quadratic_predict);
      }
      report["baselines"]["persistence"]["validate"] = EvaluatePersistence(spec, *validate);
      // Warnings only: the validation data informs the reader, never a choice.
      const auto& v = report["validate"];
      for (const char* base : {"arx", "persistence"}) {
        for (const char* mode : {"one_step", "free_run"}) {
          const auto& b = report["baselines"][base]["validate"];
          if (!v.contains(mode) || !b.contains(mode)) continue;
          const auto& fz = v[mode]["fit"];
          const auto& bf = b[mode]["fit"];
          if (fz.is_number() && bf.is_number() && fz.get<double>() < bf.get<double>()) {
            char line[160];
            std::snprintf(line, sizeof line,
                          "the model loses to %s on validation (%s FIT %.2f %% < %.2f %%)", base,
                          mode, fz.get<double>(), bf.get<double>());
            warnings.push_back(line);
          }
        }
      }
    }
    if (!o.track_csv.empty()) {
      const sysid::Series track = LoadSeries(o.track_csv, output, spec.inputs, spec);
      report["track"] =
          Track(spec, track, *model, arx, o.track_output, o.track_window, o.track_forgetting);
    }
    if (!o.predictions.empty()) {
      std::vector<std::pair<std::string, const sysid::Series*>> sets{{"train", &*train}};
      if (validate) sets.emplace_back("validate", &*validate);
      WritePredictions(o.predictions, spec, sets, predict, arx_predict);
      report["predictions_file"] = o.predictions;
    }
  }
  report["warnings"] = warnings;
  report["rule_text"] = sysid::DescribeRules(*model, 0);
  if (!o.save_model.empty()) {
    model->Save(o.save_model);
    report["model_file"] = o.save_model;
  }
  return report;
}

std::string FormatReport(const nlohmann::json& r, bool with_rules) {
  std::ostringstream out;
  char line[256];
  out << "odonata-fit: " << r["target"].get<std::string>() << " from";
  for (const auto& name : r["regressors"]) out << ' ' << name.get<std::string>();
  out << "\n  " << r["rules"].get<int>() << " rules (" << r["consequent"].get<std::string>()
      << " consequents), entropy threshold H = " << r["entropy_threshold"].get<double>()
      << ", kappa " << r["kappa"].get<double>() << ", " << r["epochs"].get<int>() << " epochs, cap "
      << r["max_rules"].get<int>() << "\n";
  if (r.contains("selection")) {
    const auto& sel = r["selection"];
    const std::string on = sel.value("scored_on", std::string("training hold-out"));
    out << "\n  model selection on " << sel["holdout_samples"].get<long>() << " samples of "
        << (on == "training hold-out" ? std::string("the training file's end") : on) << " ("
        << sel["criterion"].get<std::string>() << " NDEI; fewest rules within "
        << 100 * sel["relative_tolerance"].get<double>() << " % or "
        << sel["absolute_tolerance"].get<double>()
        << " of the best):\n      consequent  H        kappa  epochs  rules  one-step NDEI  "
           "free-run NDEI\n";
    std::size_t k = 0;
    auto num = [](const nlohmann::json& v) { return v.is_null() ? NAN : v.get<double>(); };
    for (const auto& c : sel["candidates"]) {
      const bool chosen = k == sel["chosen_index"].get<std::size_t>();
      const bool best = k == sel["best_index"].get<std::size_t>();
      std::snprintf(line, sizeof line, "    %s %-10s %-8.4g %5.2g  %6d  %5d  %13.4g  %13.4g%s\n",
                    chosen ? "*" : " ", c["consequent"].get<std::string>().c_str(),
                    c["entropy_threshold"].get<double>(), c["kappa"].get<double>(),
                    c["epochs"].get<int>(), c["rules"].get<int>(), num(c["holdout_one_step_ndei"]),
                    num(c["holdout_free_run_ndei"]), best ? "  (best)" : "");
      out << line;
      ++k;
    }
  }
  out << "\n  data       mode       model         FIT %     VAF %        RMSE\n";
  auto row = [&](const char* data, const char* model, const nlohmann::json& block) {
    for (const char* mode : {"one_step", "free_run"}) {
      if (!block.contains(mode)) continue;
      const auto& a = block[mode];
      auto get = [&](const char* k) { return a[k].is_null() ? NAN : a[k].get<double>(); };
      std::snprintf(line, sizeof line, "  %-10s %-10s %-11s %8.2f  %8.2f  %10.4g\n", data, mode,
                    model, get("fit"), get("vaf"), get("rmse"));
      out << line;
    }
  };
  for (const char* data : {"train", "validate"}) {
    if (!r.contains(data)) continue;
    row(data, "fuzzy", r[data]);
    if (r.contains("baselines")) {
      if (r["baselines"]["arx"].contains(data)) row(data, "ARX", r["baselines"]["arx"][data]);
      if (r["baselines"].contains("arx_squared_inputs") &&
          r["baselines"]["arx_squared_inputs"].contains(data)) {
        row(data, "ARX+u^2", r["baselines"]["arx_squared_inputs"][data]);
      }
      if (r["baselines"]["persistence"].contains(data))
        row(data, "persistence", r["baselines"]["persistence"][data]);
    }
  }
  if (with_rules) {
    out << "\n  rules:\n";
    int k = 1;
    for (const auto& s : r["rule_text"]) out << "  " << k++ << ". " << s.get<std::string>() << "\n";
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

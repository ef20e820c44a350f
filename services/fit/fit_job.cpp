#include "fit_job.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "io/csv_table.hpp"
#include "metrics/accuracy.hpp"
#include "metrics/accuracy_json.hpp"
#include "progress_bar.hpp"
#include "sysid/arx_model.hpp"
#include "sysid/free_run.hpp"
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
  }
  const std::string output = spec.outputs.at(0);
  std::optional<sysid::Series> train, validate;
  if (!o.train_csv.empty()) train = LoadSeries(o.train_csv, output, spec.inputs, spec);
  if (!o.validate_csv.empty()) validate = LoadSeries(o.validate_csv, output, spec.inputs, spec);
  if (!train && !model) throw std::runtime_error("nothing to do: give --train or --load-model");
  if (o.sweep && !validate)
    throw std::runtime_error("--sweep needs --validate data to score against");

  nlohmann::json report;
  ProgressBar bar(o.progress);
  fuzzy::FuzzyModelConfig cfg = o.model;
  if (o.sweep && train) {
    const auto sweep = sysid::SweepEntropyThreshold(
        spec, cfg, o.train, *train, *validate, o.sweep_options,
        [&bar](const sysid::SweepPoint& p, std::size_t k, std::size_t n) {
          char label[64];
          std::snprintf(label, sizeof label, "sweep H=%.4g: %d rules", p.threshold, p.rules);
          bar.Update(label, double(k) / double(n));
        });
    nlohmann::json points = nlohmann::json::array();
    for (const auto& p : sweep.points) {
      points.push_back(
          {{"entropy_threshold", p.threshold},
           {"rules", p.rules},
           {"validate_one_step_fit", p.validation_one_step_fit_percent},
           {"validate_free_run_fit", std::isfinite(p.validation_free_run_fit_percent)
                                         ? nlohmann::json(p.validation_free_run_fit_percent)
                                         : nlohmann::json(nullptr)}});
    }
    report["sweep"] = {{"criterion", o.sweep_options.free_run_criterion ? "free_run" : "one_step"},
                       {"tolerance_percent", o.sweep_options.tolerance_percent},
                       {"points", points},
                       {"best_index", sweep.best},
                       {"chosen_index", sweep.chosen}};
    cfg.entropy.threshold = sweep.points[sweep.chosen].threshold;
  }
  if (!o.save_ranges.empty() && train) {
    std::ofstream out(o.save_ranges);
    out << sysid::RangesToJson(sysid::RangesFromSeries(spec, *train)).dump(1) << "\n";
    if (!out) throw std::runtime_error(o.save_ranges + ": cannot write");
  }
  if (!model) {
    model.emplace(spec, cfg);
    sysid::TrainOptions topt = o.train;
    if (!o.ranges.empty()) {
      std::ifstream in(o.ranges);
      if (!in) throw std::runtime_error(o.ranges + ": cannot open ranges file");
      nlohmann::json j;
      try {
        in >> j;
        model->SetScaling(sysid::ScalingFromRanges(spec, sysid::RangesFromJson(j)));
      } catch (const std::exception& e) {
        throw std::runtime_error(o.ranges + ": " + e.what());
      }
      topt.fit_scaling = false;
    }
    topt.progress = [&bar, &topt](int epoch, long sample, long total) {
      bar.Update("epoch " + std::to_string(epoch + 1) + "/" + std::to_string(topt.epochs),
                 (epoch + double(sample) / double(total)) / topt.epochs);
    };
    model->Train(*train, topt);
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
  report["max_rules"] = fm.config().entropy.max_rules;
  report["consequent"] = fuzzy::ToString(fm.consequent().kind());
  report["epochs"] = o.load_model.empty() ? o.train.epochs : 0;
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
    if (validate) {
      report["baselines"]["arx"]["validate"] = Evaluate(spec, *validate, arx_predict);
      report["baselines"]["persistence"]["validate"] = EvaluatePersistence(spec, *validate);
    }
  }
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
      << " consequents), entropy threshold H = " << r["entropy_threshold"].get<double>() << ", cap "
      << r["max_rules"].get<int>() << "\n";
  if (r.contains("sweep")) {
    out << "\n  entropy sweep (" << r["sweep"]["criterion"].get<std::string>()
        << " validation FIT, tolerance " << r["sweep"]["tolerance_percent"].get<double>()
        << " %):\n      H        rules   one-step FIT   free-run FIT\n";
    std::size_t k = 0;
    for (const auto& p : r["sweep"]["points"]) {
      const bool chosen = k == r["sweep"]["chosen_index"].get<std::size_t>();
      const double fr =
          p["validate_free_run_fit"].is_null() ? NAN : p["validate_free_run_fit"].get<double>();
      std::snprintf(line, sizeof line, "    %s %-9.4g %5d   %10.2f %%   %10.2f %%\n",
                    chosen ? "*" : " ", p["entropy_threshold"].get<double>(), p["rules"].get<int>(),
                    p["validate_one_step_fit"].get<double>(), fr);
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
      if (r["baselines"]["persistence"].contains(data))
        row(data, "persistence", r["baselines"]["persistence"][data]);
    }
  }
  if (with_rules) {
    out << "\n  rules:\n";
    int k = 1;
    for (const auto& s : r["rule_text"]) out << "  " << k++ << ". " << s.get<std::string>() << "\n";
  }
  if (r.contains("model_file"))
    out << "\n  model saved to " << r["model_file"].get<std::string>() << "\n";
  return out.str();
}

}  // namespace odonata::fit

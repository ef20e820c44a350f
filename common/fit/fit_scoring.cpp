#include "fit/fit_scoring.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "fit/progress_bar.hpp"
#include "io/csv_table.hpp"
#include "io/csv_writer.hpp"
#include "metrics/accuracy.hpp"
#include "metrics/accuracy_alarm.hpp"
#include "metrics/accuracy_json.hpp"
#include "metrics/running_accuracy.hpp"
#include "records/record_file.hpp"
#include "sysid/model/arx_model.hpp"
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

}  // namespace odonata::fit

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
  ro.from_s = o.from_s;
  ro.to_s = o.to_s;
  ro.keep = o.keep;
  records::Record record = records::ReadRecord(path, ro);
  if (o.note)
    for (const auto& n : record.notes) o.note(n);
  const io::CsvTable& table = record.table;
  sysid::SeriesOptions so;
  so.outputs = spec.outputs;
  so.inputs = spec.inputs;
  so.time_column = o.time_column.empty() ? record.time_column : o.time_column;
  so.time_unit_s = o.time_unit_s > 0 ? o.time_unit_s : sysid::TimeUnitFromName(so.time_column);
  so.rate_hz = o.rate_hz > 0 ? o.rate_hz : record.rate_hz;
  so.max_gap = o.max_gap;
  so.from_s = o.from_s;
  so.to_s = o.to_s;
  so.keep = o.keep;
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
  if (r.rate_hz > 0) d["rate_hz"] = r.rate_hz;
  // A CSV's own time column resampled here: the grid said as a ULog's is (records).
  if (o.note && record.time_column.empty() && !so.time_column.empty()) {
    char head[160];
    std::snprintf(head, sizeof head, ": one grid at %.4g Hz%s; logged at:", r.rate_hz,
                  r.rate_chosen ? " (the slowest column's rate; --rate sets another)" : "");
    std::string note = path + head;
    for (std::size_t k = 0; k < r.columns.size(); ++k) {
      char cell[64];
      std::snprintf(cell, sizeof cell, " %.4g Hz", r.columns[k].median_rate_hz);
      note += (k ? ", " : " ") + r.columns[k].name + cell +
              (r.columns[k].held ? " (held, a flag)" : "");
    }
    o.note(note);
  }
  if (!so.time_column.empty()) {
    d["time_column"] = so.time_column;
    d["time_unit_s"] = so.time_unit_s;
    d["first_s"] = r.first_s;
    d["last_s"] = r.last_s;
    // A log's own rates are in its grid note; its table is already on the grid.
    if (record.time_column.empty())
      for (const auto& c : r.columns) d["signal_rates_hz"][c.name] = c.median_rate_hz;
    if (r.rate_chosen) d["rate_from"] = r.slowest;
  }
  if (std::isfinite(o.from_s) || std::isfinite(o.to_s))
    d["window_s"] = {std::isfinite(o.from_s) ? nlohmann::json(o.from_s) : nlohmann::json(),
                     std::isfinite(o.to_s) ? nlohmann::json(o.to_s) : nlohmann::json()};
  if (r.outside_window > 0) d["outside_window"] = r.outside_window;
  if (o.keep) {
    d["keep_when"] = o.keep->ToString();
    d["cut_by_condition"] = r.cut_by_condition;
  }
  if (!record.notes.empty()) d["grid"] = record.notes.front();
  if (data) (*data)[path] = d;
  if (warnings)
    for (const auto& w : record.warnings) warnings->push_back(w);
  // A time column counted in milliseconds but read as seconds makes a rate below 1 Hz.
  if (warnings && !so.time_column.empty() && so.time_unit_s == 1.0 && r.rate_hz > 0 &&
      r.rate_hz < 1.0 && record.time_column.empty())
    warnings->push_back(path + ": time '" + so.time_column + "' steps by " +
                        std::to_string(1.0 / r.rate_hz) +
                        " at the median, read as seconds: if it counts milliseconds, give "
                        "--time-unit ms (or name the column *_ms)");
  if (warnings && (r.bridged > 0 || r.missing > 0 || r.segments > 1)) {
    warnings->push_back(path + ": " + std::to_string(r.bridged) + " missing values bridged, " +
                        std::to_string(r.missing) + " samples dropped in longer gaps, " +
                        std::to_string(r.segments) + " segment(s) used");
  }
  return s;
}

/// Scores a predictor on a series in both modes, one block per output.
std::vector<nlohmann::json> Evaluate(const sysid::RegressorSpec& spec, const sysid::Series& s,
                                     const sysid::Predictor& predict, int horizon,
                                     const IntervalWidths* widths) {
  const Eigen::MatrixXd y = sysid::Targets(spec, s);
  const Eigen::MatrixXd one = sysid::PredictOneStep(spec, s, predict);
  bool diverged = false;
  Eigen::MatrixXd sim;
  if (spec.output_lags > 0) sim = sysid::SimulateFreeRun(spec, s, predict, &diverged);
  const bool ahead = horizon > 1 && spec.output_lags > 0;
  bool ahead_diverged = false;
  Eigen::MatrixXd k_step;
  if (ahead) k_step = sysid::PredictAhead(spec, s, predict, horizon, &ahead_diverged);
  const Eigen::MatrixXd sigma = widths ? widths->spread.At(spec, s) : Eigen::MatrixXd();
  std::vector<nlohmann::json> out;
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    nlohmann::json j;
    j["one_step"] = metrics::ScoreToJson(metrics::Score(y.col(o), one.col(o)));
    if (spec.output_lags > 0) {
      j["free_run"] = metrics::ScoreToJson(metrics::Score(y.col(o), sim.col(o)));
      if (diverged) j["free_run"]["diverged"] = true;
    }
    if (ahead) {
      j["k_step"] = metrics::ScoreToJson(metrics::Score(y.col(o), k_step.col(o)));
      j["k_step"]["horizon"] = horizon;
      if (ahead_diverged) j["k_step"]["diverged"] = true;
    }
    if (widths) {
      for (const auto& [mode, yhat] :
           {std::pair<const char*, const Eigen::MatrixXd*>{"one_step", &one},
            {"free_run", &sim},
            {"k_step", &k_step}}) {
        const Eigen::MatrixXd half = widths->HalfWidths(mode, sigma);
        if (j.contains(mode) && half.size() > 0)
          j[mode]["interval"] = IntervalScore(y.col(o), yhat->col(o), half.col(o), *widths);
      }
    }
    out.push_back(j);
  }
  return out;
}

/// Persistence ŷ(t) = y(t−1) one step ahead, y(t−K) K steps ahead (held from the last measured
/// value before the segment's first target when t−K is before it); free run holds the last
/// measured value before each segment's first target. One block per output.
std::vector<nlohmann::json> EvaluatePersistence(const sysid::RegressorSpec& spec,
                                                const sysid::Series& s, int horizon) {
  const auto targets = sysid::TargetRows(spec, s);
  const auto rows = static_cast<Eigen::Index>(targets.size());
  const Eigen::MatrixXd y = sysid::Targets(spec, s);
  const bool ahead = horizon > 1 && spec.output_lags > 0;
  Eigen::MatrixXd one(rows, y.cols()), held(rows, y.cols()), k_step(rows, y.cols());
  Eigen::Index segment_start = 0;  // the row of the segment's first target
  for (Eigen::Index r = 0; r < rows; ++r) {
    const Eigen::Index t = targets[static_cast<std::size_t>(r)];
    const bool first = r == 0 || targets[static_cast<std::size_t>(r) - 1] != t - 1;
    if (first) segment_start = r;
    one.row(r) = s.outputs.row(std::max<Eigen::Index>(t - 1, 0));
    if (first)
      held.row(r) = s.outputs.row(std::max<Eigen::Index>(t - 1, 0));
    else
      held.row(r) = held.row(r - 1);
    if (ahead) {
      const Eigen::Index back = std::min<Eigen::Index>(horizon, r - segment_start + 1);
      k_step.row(r) = s.outputs.row(std::max<Eigen::Index>(t - back, 0));
    }
  }
  std::vector<nlohmann::json> out;
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    nlohmann::json j;
    j["one_step"] = metrics::ScoreToJson(metrics::Score(y.col(o), one.col(o)));
    if (spec.output_lags > 0)
      j["free_run"] = metrics::AccuracyToJson(metrics::Score(y.col(o), held.col(o)));
    if (ahead) {
      j["k_step"] = metrics::ScoreToJson(metrics::Score(y.col(o), k_step.col(o)));
      j["k_step"]["horizon"] = horizon;
    }
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
                      const sysid::Predictor& fuzzy, const sysid::Predictor& arx, int horizon,
                      const IntervalWidths* widths) {
  const auto no = spec.outputs.size();
  const bool ahead = horizon > 1 && spec.output_lags > 0;
  // The modes whose intervals are written, in column order.
  std::vector<std::string> bands;
  if (widths)
    for (const char* mode : {"one_step", "free_run", "k_step"})
      if (widths->half_width.count(mode) > 0 && (std::string(mode) != "k_step" || ahead))
        bands.emplace_back(mode);
  std::vector<std::string> header{"set", "sample"};
  for (const auto& name : spec.outputs) {
    const std::string sfx = no > 1 ? "_" + name : "";
    for (const char* c :
         {"measured", "fuzzy_one_step", "fuzzy_free_run", "arx_one_step", "arx_free_run"})
      header.push_back(c + sfx);
    if (ahead)
      for (const char* c : {"fuzzy_k_step", "arx_k_step"}) header.push_back(c + sfx);
    for (const auto& band : bands) {
      header.push_back("fuzzy_" + band + "_lower" + sfx);
      header.push_back("fuzzy_" + band + "_upper" + sfx);
    }
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
    std::vector<Eigen::MatrixXd> half;  // per band: each target's half widths
    if (widths) {
      const Eigen::MatrixXd sigma = widths->spread.At(spec, *s);
      for (const auto& band : bands) half.push_back(widths->HalfWidths(band, sigma));
    }
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
        for (std::size_t b = 0; b < bands.size(); ++b) {
          const double centre = bands[b] == "one_step"   ? f1(r, o)
                                : bands[b] == "free_run" ? fr(r, o)
                                                         : fk(r, o);
          row.push_back(centre - half[b](r, o));
          row.push_back(centre + half[b](r, o));
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

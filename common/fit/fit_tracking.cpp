#include "fit/fit_tracking.hpp"

#include <optional>
#include <vector>

#include "io/csv_writer.hpp"
#include "metrics/accuracy.hpp"
#include "metrics/accuracy_alarm.hpp"
#include "metrics/accuracy_json.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit {

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

}  // namespace odonata::fit

#include "model_messages/prediction_message.hpp"

#include <cmath>

#include "contract/precondition.hpp"

namespace odonata::model_messages {

odonata::prediction_t ToPredictionMessage(const sysid::SampleReport& report,
                                          const std::vector<std::string>& names, int64_t seq,
                                          int64_t utime) {
  ODONATA_EXPECTS(static_cast<Eigen::Index>(names.size()) == report.measured.size());
  odonata::prediction_t p;
  p.utime = utime;
  p.seq = seq;
  p.sample = report.index;
  p.num_outputs = static_cast<int32_t>(names.size());
  p.names = names;
  for (Eigen::Index o = 0; o < report.measured.size(); ++o) {
    p.measured.push_back(report.measured(o));
    p.predicted.push_back(report.predicted(o));
    p.free_run.push_back(report.free_run(o));
    p.next.push_back(report.next(o));
    p.rules.push_back(report.rules(o));
    p.max_entropy.push_back(report.max_entropy(o));
    p.arx_predicted.push_back(report.arx_predicted(o));
    p.arx_free_run.push_back(report.arx_free_run(o));
    p.linear_share.push_back(o < report.linear_share.size() ? report.linear_share(o) : 0.0);
  }
  // +∞ (too few residuals yet) travels as −1: receivers drop messages carrying non-finite values.
  const auto width = [](const Eigen::VectorXd& w, Eigen::Index o) {
    return o < w.size() && std::isfinite(w(o)) ? w(o) : -1.0;
  };
  p.interval_level = report.interval_level;
  for (Eigen::Index o = 0; o < report.measured.size(); ++o)
    p.half_width.push_back(width(report.half_width, o));
  p.num_intervals = static_cast<int32_t>(p.half_width.size());
  p.learning = report.learned ? 1 : 0;
  p.horizon = report.ahead.size() > 0 ? report.horizon : 0;
  p.num_ahead = p.horizon > 0 ? p.num_outputs : 0;
  for (Eigen::Index o = 0; o < report.ahead.size() && p.horizon > 0; ++o) {
    p.ahead.push_back(report.ahead(o));
    p.arx_ahead.push_back(report.arx_ahead(o));
    p.ahead_half_width.push_back(width(report.ahead_half_width, o));
  }
  p.num_ahead_intervals = static_cast<int32_t>(p.ahead_half_width.size());
  for (Eigen::Index o = 0; o < report.measured.size(); ++o)
    p.free_run_half_width.push_back(width(report.free_run_half_width, o));
  p.num_free_run_intervals = static_cast<int32_t>(p.free_run_half_width.size());
  if (static_cast<Eigen::Index>(report.seen_enough.size()) == report.measured.size())
    for (const sysid::SettlingState s : report.seen_enough)
      p.seen_enough.push_back(static_cast<int8_t>(s));
  p.num_seen_enough = static_cast<int32_t>(p.seen_enough.size());
  return p;
}

}  // namespace odonata::model_messages

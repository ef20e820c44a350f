#include "monitoring/prediction_scoreboard.hpp"

#include <cmath>
#include <stdexcept>

#include "metrics/accuracy_json.hpp"

namespace odonata::monitoring {

nlohmann::json PredictorScores::ToJson(int horizon) const {
  nlohmann::json s = {{"one_step", metrics::AccuracyToJson(one_step.total.Get())},
                      {"free_run", metrics::AccuracyToJson(free_run.total.Get())},
                      {"window_one_step", metrics::AccuracyToJson(one_step.window.Get())},
                      {"window_free_run", metrics::AccuracyToJson(free_run.window.Get())}};
  if (ahead.scored()) {
    s["ahead"] = metrics::AccuracyToJson(ahead.total.Get());
    s["window_ahead"] = metrics::AccuracyToJson(ahead.window.Get());
    s["horizon"] = horizon;
  }
  return s;
}

namespace {

// A prediction whose arrays disagree with its outputs or carry NaN or Inf: refused whole.
void RefuseMalformed(const Prediction& p) {
  const std::size_t n = p.names.size();
  if (p.measured.size() != n || p.predicted.size() != n || p.free_run.size() != n ||
      p.rules.size() != n || p.arx_predicted.size() != p.arx_free_run.size() ||
      (!p.arx_predicted.empty() && p.arx_predicted.size() != n)) {
    throw std::invalid_argument("prediction arrays disagree with num_outputs");
  }
  const bool arx = !p.arx_predicted.empty();
  const bool ahead = p.horizon > 0;
  if (!p.linear_share.empty() && p.linear_share.size() != n)
    throw std::invalid_argument("prediction's linear_share disagrees with num_outputs");
  if (p.horizon < 0 || p.horizon == 1 || (ahead && p.ahead.size() != n) ||
      p.arx_ahead.size() != (ahead && arx ? n : 0) || (!ahead && !p.ahead.empty()))
    throw std::invalid_argument("prediction's K-step arrays disagree with its horizon " +
                                std::to_string(p.horizon));
  if ((!p.half_width.empty() && p.half_width.size() != n) ||
      (!p.ahead_half_width.empty() && p.ahead_half_width.size() != (ahead ? n : 0)) ||
      (!p.free_run_half_width.empty() && p.free_run_half_width.size() != n))
    throw std::invalid_argument("prediction's interval arrays disagree with num_outputs");
  if (!p.seen_enough.empty() && p.seen_enough.size() != n)
    throw std::invalid_argument("prediction's seen_enough disagrees with num_outputs");
  for (const int s : p.seen_enough)
    if (s < 0 || s > 2) throw std::invalid_argument("prediction with an unknown seen_enough state");
  for (const auto* widths : {&p.half_width, &p.ahead_half_width, &p.free_run_half_width})
    for (const double h : *widths)
      if (std::isnan(h)) throw std::invalid_argument("prediction with a NaN interval");
  for (std::size_t o = 0; o < n; ++o) {
    if (!std::isfinite(p.measured[o]) || !std::isfinite(p.predicted[o]) ||
        !std::isfinite(p.free_run[o]) ||
        (arx && (!std::isfinite(p.arx_predicted[o]) || !std::isfinite(p.arx_free_run[o]))) ||
        (ahead && !std::isfinite(p.ahead[o])) || (ahead && arx && !std::isfinite(p.arx_ahead[o]))) {
      throw std::invalid_argument("prediction with NaN or Inf for " + p.names[o]);
    }
  }
}

}  // namespace

std::vector<ScoreEvent> PredictionScoreboard::Add(const Prediction& p) {
  // Checked before anything changes: a rejected prediction must not move the sample counter
  // (the genuine one for that sample would then be dropped as a duplicate).
  RefuseMalformed(p);
  const std::size_t n = p.names.size();
  const bool arx = !p.arx_predicted.empty();
  const bool ahead = p.horizon > 0;
  const std::string leap = leaps_.Problem("prediction sample", p.sample, last_sample_);
  if (!leap.empty()) throw std::invalid_argument(leap);
  if (last_sample_ >= 0 && p.sample == last_sample_) {
    throw std::invalid_argument("duplicate prediction for sample " + std::to_string(p.sample));
  }
  // Bounded before anything changes: at most kMaxOutputs names in the run this joins.
  const bool new_run = last_sample_ >= 0 && p.sample < last_sample_;
  std::size_t names = new_run ? 0 : outputs_.size();
  for (std::size_t o = 0; o < n; ++o)
    if (new_run || outputs_.count(p.names[o]) == 0) ++names;
  if (names > kMaxOutputs)
    throw std::invalid_argument("prediction would score " + std::to_string(names) +
                                " outputs in one run, over " + std::to_string(kMaxOutputs));
  std::vector<ScoreEvent> events;
  if (new_run) {
    // The plant restarted (a new run, e.g. validation after training): score it on its own and
    // keep the finished run in the summary. Only the run's own scores: a summary that held the
    // earlier runs doubled in size with every new run.
    ScoreEvent e;
    e.kind = ScoreEvent::Kind::kNewRun;
    e.sample = p.sample;
    e.previous = last_sample_;
    events.push_back(e);
    finished_runs_.push_back(RunSummary());
    if (finished_runs_.size() > kMaxFinishedRuns) finished_runs_.erase(finished_runs_.begin());
    outputs_.clear();
    order_.clear();
    gaps_ = 0;
  } else if (last_sample_ >= 0 && p.sample > last_sample_ + 1) {
    gaps_ += p.sample - last_sample_ - 1;
  }
  last_sample_ = p.sample;
  for (std::size_t o = 0; o < n; ++o) {
    const std::string& name = p.names[o];
    auto it = outputs_.find(name);
    if (it == outputs_.end()) {
      metrics::AccuracyAlarmOptions alarm;
      alarm.window = options_.alarm_window_samples;
      alarm.drop_points = options_.alarm_drop_points;
      it = outputs_.emplace(name, Output(options_.window_samples, alarm)).first;
      order_.push_back(name);
    }
    Output& out = it->second;
    const double y = p.measured[o];
    out.fuzzy.one_step.Add(y, p.predicted[o]);
    out.fuzzy.free_run.Add(y, p.free_run[o]);
    out.rules = p.rules[o];
    if (o < p.half_width.size() || o < p.ahead_half_width.size() ||
        o < p.free_run_half_width.size()) {
      // A level changed within a run (a reconfigured identifier): its tallies start again.
      if (out.interval_level != p.interval_level) {
        out.one_step_interval = {};
        out.ahead_interval = {};
        out.free_run_interval = {};
        out.interval_level = p.interval_level;
      }
      if (o < p.half_width.size()) out.one_step_interval.Add(y, p.predicted[o], p.half_width[o]);
      if (o < p.ahead_half_width.size())
        out.ahead_interval.Add(y, p.ahead[o], p.ahead_half_width[o]);
      if (o < p.free_run_half_width.size())
        out.free_run_interval.Add(y, p.free_run[o], p.free_run_half_width[o]);
    }
    if (o < p.seen_enough.size()) out.seen_enough = p.seen_enough[o];
    if (o < p.linear_share.size() && p.linear_share[o] > 0.0) ++out.outside;
    if (ahead) {
      // A horizon changed within a run (a reconfigured identifier): its K-step scores start again.
      if (out.horizon != p.horizon) {
        out.fuzzy.ahead = ModeScore(options_.window_samples);
        out.arx.ahead = ModeScore(options_.window_samples);
        out.horizon = p.horizon;
      }
      out.fuzzy.ahead.Add(y, p.ahead[o]);
      if (arx) out.arx.ahead.Add(y, p.arx_ahead[o]);
    }
    if (arx) {
      out.arx.one_step.Add(y, p.arx_predicted[o]);
      out.arx.free_run.Add(y, p.arx_free_run[o]);
      // Like with like: K steps ahead when the predictions carry a horizon (a loop that
      // integrates, where one step ahead says little), else one step ahead.
      const bool k_step = out.horizon > 0 && out.arx.ahead.scored();
      const ModeScore& mine = k_step ? out.fuzzy.ahead : out.fuzzy.one_step;
      const ModeScore& linear = k_step ? out.arx.ahead : out.arx.one_step;
      if (mine.window.full() && linear.window.full()) {
        const double fit = mine.window.Get().fit_percent;
        const double reference = linear.window.Get().fit_percent;
        const int h = k_step ? out.horizon : 1;
        if (fit <= reference && !out.behind_arx) {
          events.push_back({ScoreEvent::Kind::kBehindArx, name, p.sample, 0, fit, reference, h});
          out.behind_arx = true;
        } else if (fit > reference + options_.arx_margin_points && out.behind_arx) {
          events.push_back({ScoreEvent::Kind::kAheadOfArx, name, p.sample, 0, fit, reference, h});
          out.behind_arx = false;
        }
      }
    }
    if (const auto a = out.alarm.Push(static_cast<long>(p.sample), p.measured[o], p.predicted[o])) {
      const bool alarm = a->kind == metrics::AccuracyEvent::Kind::kAlarm;
      events.push_back({alarm ? ScoreEvent::Kind::kAlarm : ScoreEvent::Kind::kRecovered, name,
                        a->sample, 0, a->window_fit, a->reference_fit, 1});
      if (out.alarm_events.size() >= kMaxAlarmEvents) {
        out.alarm_events.erase(out.alarm_events.begin());
      }
      out.alarm_events.push_back({{"kind", alarm ? "alarm" : "recovered"},
                                  {"sample", a->sample},
                                  {"tracking_fit", a->window_fit},
                                  {"reference_fit", a->reference_fit}});
    }
    if (out.fuzzy.one_step.window.full()) {
      const double fit = out.fuzzy.one_step.window.Get().fit_percent;
      if (fit < options_.warn_fit_percent && !out.warned) {
        events.push_back({ScoreEvent::Kind::kLowFit, name, p.sample, 0, fit, 0, 1});
        out.warned = true;
      } else if (fit >= options_.warn_fit_percent && out.warned) {
        events.push_back({ScoreEvent::Kind::kLowFitCleared, name, p.sample, 0, fit, 0, 1});
        out.warned = false;
      }
    }
  }
  return events;
}

void PredictionScoreboard::Reset() {
  outputs_.clear();
  order_.clear();
  last_sample_ = -1;
  gaps_ = 0;
}

bool PredictionScoreboard::Warned(const std::string& output) const {
  const auto it = outputs_.find(output);
  return it != outputs_.end() && it->second.warned;
}

bool PredictionScoreboard::BehindArx(const std::string& output) const {
  const auto it = outputs_.find(output);
  return it != outputs_.end() && it->second.behind_arx;
}

bool PredictionScoreboard::Alarmed(const std::string& output) const {
  const auto it = outputs_.find(output);
  return it != outputs_.end() && it->second.alarm.alarmed();
}

nlohmann::json PredictionScoreboard::RunSummary() const {
  nlohmann::json j;
  j["last_sample"] = last_sample_;
  j["gaps"] = gaps_;
  for (const auto& name : order_) {
    const Output& o = outputs_.at(name);
    nlohmann::json out = o.fuzzy.ToJson(o.horizon);
    out["rules"] = o.rules;
    // Outside the data the model was trained on (docs/identifier.md §7.3): how often it met it.
    out["samples_outside"] = o.outside;
    out["alarm_events"] = o.alarm_events;
    out["alarmed"] = o.alarm.alarmed();
    if (o.interval_level > 0.0) {
      out["interval"] = {{"level", o.interval_level}, {"one_step", o.one_step_interval.ToJson()}};
      if (o.ahead_interval.scored > 0) out["interval"]["k_step"] = o.ahead_interval.ToJson();
      if (o.free_run_interval.scored > 0)
        out["interval"]["free_run"] = o.free_run_interval.ToJson();
    }
    if (o.seen_enough >= 0) out["seen_enough"] = o.seen_enough;
    if (o.has_arx()) {
      out["arx"] = o.arx.ToJson(o.horizon);
      out["behind_arx"] = o.behind_arx;
    }
    j["outputs"][name] = out;
  }
  return j;
}

nlohmann::json PredictionScoreboard::Summary() const {
  nlohmann::json j = RunSummary();
  if (!finished_runs_.empty()) j["previous_runs"] = finished_runs_;
  return j;
}

}  // namespace odonata::monitoring

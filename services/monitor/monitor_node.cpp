#include "monitor_node.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include "metrics/accuracy_json.hpp"
#include "pipeline/sequence_window.hpp"

namespace odonata::monitor {
namespace {
std::chrono::microseconds Period(double seconds) {
  return std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6));
}
}  // namespace

MonitorNode::MonitorNode(bus::BusNode& bus, MonitorOptions options)
    : bus_(bus), options_(std::move(options)) {
  const auto& ch = bus_.channels();
  bus_.Subscribe<odonata::prediction_t>(ch.prediction, [this](const auto& m) { OnPrediction(m); });
  bus_.Subscribe<odonata::heartbeat_t>(ch.heartbeat, [this](const auto& m) { OnHeartbeat(m); });
  bus_.Subscribe<odonata::model_snapshot_t>(ch.model, [this](const auto& m) { OnSnapshot(m); });
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
  bus_.Every(Period(1.0 / options_.publish_hz), [this] { PublishAccuracy(); });
  bus_.Every(Period(0.5), [this] { CheckPeers(); });
  bus_.Every(Period(options_.live_table ? 0.5 : options_.print_period_s), [this] { Print(); });
  bus_.OnShutdown([this] {
    Print();
    if (!options_.summary_json.empty()) {
      std::ofstream out(options_.summary_json);
      out << Summary().dump(1) << "\n";
      if (!out) throw std::runtime_error(options_.summary_json + ": cannot write summary");
    }
  });
  bus_.SetState("running");
}

void MonitorNode::OnPrediction(const odonata::prediction_t& m) {
  const auto n = static_cast<std::size_t>(m.num_outputs);
  if (m.num_outputs < 0 || m.names.size() != n || m.measured.size() != n ||
      m.predicted.size() != n || m.free_run.size() != n || m.rules.size() != n) {
    throw std::invalid_argument("prediction arrays disagree with num_outputs");
  }
  const std::string leap = leaps_.Problem("prediction sample", m.sample, last_sample_);
  if (!leap.empty()) throw std::invalid_argument(leap);
  if (last_sample_ >= 0 && m.sample == last_sample_) {
    throw std::invalid_argument("duplicate prediction for sample " + std::to_string(m.sample));
  }
  // Checked before anything changes: a rejected prediction must not move the sample counter
  // (the genuine one for that sample would then be dropped as a duplicate).
  for (std::size_t o = 0; o < n; ++o) {
    if (!std::isfinite(m.measured[o]) || !std::isfinite(m.predicted[o]) ||
        !std::isfinite(m.free_run[o])) {
      throw std::invalid_argument("prediction with NaN or Inf for " + m.names[o]);
    }
  }
  if (last_sample_ >= 0 && m.sample < last_sample_) {
    // The plant restarted (a new run, e.g. validation after training): score it on its own and
    // keep the finished run in the summary (the latest kMaxFinishedRuns of them). Only the run's
    // own scores: a summary that held the earlier runs doubled in size with every new run.
    std::fprintf(stderr, "[%s] new run from sample %lld (the previous one ended at %lld)\n",
                 bus_.options().instance.c_str(), static_cast<long long>(m.sample),
                 static_cast<long long>(last_sample_));
    finished_runs_.push_back(RunSummary());
    if (finished_runs_.size() > kMaxFinishedRuns) finished_runs_.erase(finished_runs_.begin());
    outputs_.clear();
    order_.clear();
    gaps_ = 0;
  } else if (last_sample_ >= 0 && m.sample > last_sample_ + 1) {
    gaps_ += m.sample - last_sample_ - 1;
  }
  last_sample_ = m.sample;
  for (std::size_t o = 0; o < n; ++o) {
    auto it = outputs_.find(m.names[o]);
    if (it == outputs_.end()) {
      metrics::AccuracyAlarmOptions alarm;
      alarm.window = options_.alarm_window_samples;
      alarm.drop_points = options_.alarm_drop_points;
      it = outputs_.emplace(m.names[o], Output(options_.window_samples, alarm)).first;
      order_.push_back(m.names[o]);
    }
    Output& out = it->second;
    out.total_one_step.Add(m.measured[o], m.predicted[o]);
    out.window_one_step.Add(m.measured[o], m.predicted[o]);
    out.total_free_run.Add(m.measured[o], m.free_run[o]);
    out.window_free_run.Add(m.measured[o], m.free_run[o]);
    out.rules = m.rules[o];
    if (const auto e = out.alarm.Push(static_cast<long>(m.sample), m.measured[o], m.predicted[o])) {
      const bool alarm = e->kind == metrics::AccuracyEvent::Kind::kAlarm;
      std::fprintf(stderr,
                   alarm ? "[%s] ALARM: %s accuracy fell at sample %ld: tracking FIT %.1f %% "
                           "against a settled %.1f %%\n"
                         : "[%s] RECOVERED: %s accuracy back at sample %ld: tracking FIT %.1f "
                           "%% against the %.1f %% before the alarm\n",
                   bus_.options().instance.c_str(), m.names[o].c_str(), e->sample, e->window_fit,
                   e->reference_fit);
      if (out.alarm_events.size() >= kMaxAlarmEvents) {
        out.alarm_events.erase(out.alarm_events.begin());
      }
      out.alarm_events.push_back({{"kind", alarm ? "alarm" : "recovered"},
                                  {"sample", e->sample},
                                  {"tracking_fit", e->window_fit},
                                  {"reference_fit", e->reference_fit}});
    }
    if (out.window_one_step.full()) {
      const double fit = out.window_one_step.Get().fit_percent;
      if (fit < options_.warn_fit_percent && !out.warned) {
        std::fprintf(
            stderr, "[%s] WARNING: %s one-step FIT %.1f %% over the last %zu samples (< %.0f %%)\n",
            bus_.options().instance.c_str(), m.names[o].c_str(), fit, options_.window_samples,
            options_.warn_fit_percent);
        out.warned = true;
      } else if (fit >= options_.warn_fit_percent && out.warned) {
        std::fprintf(stderr, "[%s] %s one-step FIT back to %.1f %%\n",
                     bus_.options().instance.c_str(), m.names[o].c_str(), fit);
        out.warned = false;
      }
    }
  }
}

void MonitorNode::OnHeartbeat(const odonata::heartbeat_t& m) {
  if (peers_.size() >= kMaxPeers && peers_.count(m.instance) == 0) {
    const auto oldest = std::min_element(
        peers_.begin(), peers_.end(),
        [](const auto& a, const auto& b) { return a.second.last_seen < b.second.last_seen; });
    peers_.erase(oldest);
  }
  Peer& p = peers_[m.instance];
  if (p.silent) {
    std::fprintf(stderr, "[%s] %s (%s) is back, state %s\n", bus_.options().instance.c_str(),
                 m.instance.c_str(), m.service.c_str(), m.state.c_str());
  }
  p.service = m.service;
  p.state = m.state;
  p.last_seen = std::chrono::steady_clock::now();
  p.silent = false;
  p.decode_errors = m.decode_errors;
  p.dropped = m.dropped;
  p.gaps = m.gaps;
  if (m.skipped > p.skipped || m.repeated > p.repeated) {
    // A real-time plant falling behind: said once per heartbeat that shows new ones, so a loaded
    // machine's degradation is visible where the accuracy is watched.
    std::fprintf(stderr,
                 "[%s] %s: %lld commands never applied, %lld applied twice or more so far\n",
                 bus_.options().instance.c_str(), m.instance.c_str(),
                 static_cast<long long>(m.skipped), static_cast<long long>(m.repeated));
  }
  p.skipped = m.skipped;
  p.repeated = m.repeated;
}

void MonitorNode::OnSnapshot(const odonata::model_snapshot_t& m) {
  if (m.instance.empty()) return;
  if (snapshots_.size() >= kMaxSnapshots && snapshots_.count(m.instance) == 0) {
    const auto oldest = std::min_element(
        snapshots_.begin(), snapshots_.end(),
        [](const auto& a, const auto& b) { return a.second.received < b.second.received; });
    snapshots_.erase(oldest);
  }
  snapshots_[m.instance] = CachedSnapshot{m, std::chrono::steady_clock::now()};
}

void MonitorNode::OnControl(const odonata::control_t& m) {
  if (m.command == odonata::control_t::PUBLISH_SNAPSHOT) {
    // An identifier starting up asks for its last snapshot: answer from the cache.
    const auto it = snapshots_.find(m.target);
    if (it != snapshots_.end()) bus_.Publish(bus_.channels().model, it->second.snapshot);
    return;
  }
  if (!bus_.AcceptControl(m)) return;
  if (m.command == odonata::control_t::RESET) {
    std::fprintf(stderr, "[%s] reset by '%s': the scores so far are discarded\n",
                 bus_.options().instance.c_str(), m.sender.c_str());
    outputs_.clear();
    order_.clear();
    last_sample_ = -1;
    gaps_ = 0;
  } else if (m.command == odonata::control_t::SHUTDOWN) {
    bus_.Stop(0);
  }
}

void MonitorNode::CheckPeers() {
  const auto now = std::chrono::steady_clock::now();
  for (auto& [instance, p] : peers_) {
    const double silent_s = std::chrono::duration<double>(now - p.last_seen).count();
    if (!p.silent && p.state != "stopping" && silent_s > options_.heartbeat_timeout_s) {
      std::fprintf(stderr, "[%s] WARNING: %s (%s) silent for %.1f s (last state %s)\n",
                   bus_.options().instance.c_str(), instance.c_str(), p.service.c_str(), silent_s,
                   p.state.c_str());
      p.silent = true;
    }
  }
}

void MonitorNode::PublishAccuracy() {
  if (order_.empty()) return;
  odonata::accuracy_t a;
  a.utime = bus::NowUtime();
  a.seq = accuracy_seq_++;
  a.last_sample = last_sample_;
  a.gaps = gaps_;
  a.num_outputs = static_cast<int32_t>(order_.size());
  a.names = order_;
  a.window_samples = 0;
  a.total_samples = 0;
  const auto append = [](const auto& score, std::vector<double>* fit, std::vector<double>* vaf,
                         std::vector<double>* rmse) {
    fit->push_back(score.fit_percent);
    vaf->push_back(score.vaf_percent);
    rmse->push_back(score.rmse);
  };
  for (const auto& name : order_) {
    const Output& o = outputs_.at(name);
    a.window_samples = static_cast<int32_t>(o.window_one_step.size());
    a.total_samples = o.total_one_step.samples();
    append(o.window_one_step.Get(), &a.window_fit_one_step, &a.window_vaf_one_step,
           &a.window_rmse_one_step);
    append(o.total_one_step.Get(), &a.total_fit_one_step, &a.total_vaf_one_step,
           &a.total_rmse_one_step);
    append(o.window_free_run.Get(), &a.window_fit_free_run, &a.window_vaf_free_run,
           &a.window_rmse_free_run);
    append(o.total_free_run.Get(), &a.total_fit_free_run, &a.total_vaf_free_run,
           &a.total_rmse_free_run);
    a.rules.push_back(o.rules);
  }
  bus_.Publish(bus_.channels().accuracy, a);
}

nlohmann::json MonitorNode::Summary() const {
  nlohmann::json j = RunSummary();
  if (!finished_runs_.empty()) j["previous_runs"] = finished_runs_;
  for (const auto& [instance, p] : peers_) {
    j["services"][instance] = {
        {"service", p.service},  {"state", p.state}, {"decode_errors", p.decode_errors},
        {"dropped", p.dropped},  {"gaps", p.gaps},   {"skipped", p.skipped},
        {"repeated", p.repeated}};
  }
  return j;
}

nlohmann::json MonitorNode::RunSummary() const {
  nlohmann::json j;
  j["last_sample"] = last_sample_;
  j["gaps"] = gaps_;
  for (const auto& name : order_) {
    const Output& o = outputs_.at(name);
    j["outputs"][name] = {{"rules", o.rules},
                          {"one_step", metrics::AccuracyToJson(o.total_one_step.Get())},
                          {"free_run", metrics::AccuracyToJson(o.total_free_run.Get())},
                          {"window_one_step", metrics::AccuracyToJson(o.window_one_step.Get())},
                          {"alarm_events", o.alarm_events},
                          {"alarmed", o.alarm.alarmed()}};
  }
  return j;
}

void MonitorNode::Print() {
  std::string text;
  char line[256];
  std::snprintf(line, sizeof line, "%-16s %6s %10s %10s %10s %10s %9s\n", "output", "rules",
                "FIT win %", "FIT all %", "free-run %", "RMSE", "samples");
  text += line;
  for (const auto& name : order_) {
    const Output& o = outputs_.at(name);
    const auto t = o.total_one_step.Get();
    std::snprintf(line, sizeof line, "%-16s %6d %10.2f %10.2f %10.2f %10.4g %9ld\n", name.c_str(),
                  o.rules, o.window_one_step.Get().fit_percent, t.fit_percent,
                  o.total_free_run.Get().fit_percent, t.rmse, t.samples);
    text += line;
  }
  for (const auto& [instance, p] : peers_) {
    std::snprintf(line, sizeof line,
                  "  %-22s %-10s decode errors %lld, dropped %lld, gaps %lld, skipped %lld, "
                  "repeated %lld%s\n",
                  instance.c_str(), p.state.c_str(), static_cast<long long>(p.decode_errors),
                  static_cast<long long>(p.dropped), static_cast<long long>(p.gaps),
                  static_cast<long long>(p.skipped), static_cast<long long>(p.repeated),
                  p.silent ? "  SILENT" : "");
    text += line;
  }
  if (options_.live_table) {
    // Move up over the previous table and redraw it in place.
    if (printed_lines_ > 0) std::printf("\033[%zuA\033[J", printed_lines_);
    std::fputs(text.c_str(), stdout);
    printed_lines_ = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  } else if (!order_.empty()) {
    std::fputs(text.c_str(), stdout);
  }
  std::fflush(stdout);
}

}  // namespace odonata::monitor

#include "monitor_node.hpp"

#include "io/atomic_file.hpp"
#include "metrics/accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>

#include <sys/ioctl.h>
#include <unistd.h>
#include <string>

#include "monitoring/prediction_from_message.hpp"

namespace odonata::monitor {
namespace {
// The terminal's width in columns (80 when stdout is not a terminal that says).
std::size_t TerminalColumns() {
  winsize w{};
  if (ioctl(STDOUT_FILENO, TIOCGWINSZ, &w) == 0 && w.ws_col > 0) return w.ws_col;
  return 80;
}

// Each line of `text` cut to `columns` bytes (the table is ASCII).
std::string ClipLines(const std::string& text, std::size_t columns) {
  std::string out;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    out += text.substr(begin, std::min(end - begin, columns));
    out += '\n';
    begin = end + 1;
  }
  return out;
}

// "one-step" or "50-step": the mode a score or a comparison is in.
std::string ModeName(int horizon) {
  return horizon > 1 ? std::to_string(horizon) + "-step" : std::string("one-step");
}
std::chrono::microseconds Period(double seconds) {
  return std::chrono::microseconds(static_cast<int64_t>(seconds * 1e6));
}

}  // namespace

MonitorNode::MonitorNode(bus::BusNode& bus, MonitorOptions options)
    : bus_(bus), options_(std::move(options)), scores_(options_.scoring) {
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
      io::WriteFileAtomically(options_.summary_json, Summary().dump(1) + "\n");
    }
  });
  bus_.SetState("running");
}

void MonitorNode::OnPrediction(const odonata::prediction_t& m) {
  if (m.num_outputs < 0 || m.names.size() != static_cast<std::size_t>(m.num_outputs))
    throw std::invalid_argument("prediction arrays disagree with num_outputs");
  const monitoring::Prediction p = monitoring::PredictionFromMessage(m);
  const char* me = bus_.options().instance.c_str();
  using Kind = monitoring::ScoreEvent::Kind;
  for (const auto& e : scores_.Add(p)) {
    const char* output = e.output.c_str();
    switch (e.kind) {
      case Kind::kNewRun:
        std::fprintf(stderr, "[%s] new run from sample %lld (the previous one ended at %lld)\n", me,
                     static_cast<long long>(e.sample), static_cast<long long>(e.previous));
        break;
      case Kind::kAlarm:
        std::fprintf(stderr,
                     "[%s] ALARM: %s accuracy fell at sample %lld: tracking FIT %.1f %% against "
                     "a settled %.1f %%\n",
                     me, output, static_cast<long long>(e.sample), e.fit, e.reference);
        break;
      case Kind::kRecovered:
        std::fprintf(stderr,
                     "[%s] RECOVERED: %s accuracy back at sample %lld: tracking FIT %.1f %% "
                     "against the %.1f %% before the alarm\n",
                     me, output, static_cast<long long>(e.sample), e.fit, e.reference);
        break;
      case Kind::kLowFit:
        std::fprintf(
            stderr, "[%s] WARNING: %s one-step FIT %.1f %% over the last %zu samples (< %.0f %%)\n",
            me, output, e.fit, options_.scoring.window_samples, options_.scoring.warn_fit_percent);
        break;
      case Kind::kLowFitCleared:
        std::fprintf(stderr, "[%s] %s one-step FIT back to %.1f %%\n", me, output, e.fit);
        break;
      case Kind::kBehindArx:
        std::fprintf(stderr,
                     "[%s] WARNING: %s: the fuzzy model does not beat linear at sample %lld: "
                     "%s FIT %.2f %% against the live ARX's %.2f %% over the last %zu samples\n",
                     me, output, static_cast<long long>(e.sample), ModeName(e.horizon).c_str(),
                     e.fit, e.reference, options_.scoring.window_samples);
        break;
      case Kind::kAheadOfArx:
        std::fprintf(stderr,
                     "[%s] %s: the fuzzy model beats the live ARX again at sample %lld: %s FIT "
                     "%.2f %% against %.2f %%\n",
                     me, output, static_cast<long long>(e.sample), ModeName(e.horizon).c_str(),
                     e.fit, e.reference);
        break;
    }
  }
}

void MonitorNode::OnHeartbeat(const odonata::heartbeat_t& m) {
  const monitoring::Heartbeat hb{m.instance, m.service, m.state,    m.decode_errors, m.dropped,
                                 m.gaps,     m.skipped, m.repeated, m.detail};
  for (const auto& e : peers_.OnHeartbeat(hb, std::chrono::steady_clock::now())) {
    if (e.kind == monitoring::PeerEvent::Kind::kBack) {
      std::fprintf(stderr, "[%s] %s (%s) is back, state %s\n", bus_.options().instance.c_str(),
                   e.instance.c_str(), e.service.c_str(), e.state.c_str());
    } else {
      std::fprintf(stderr,
                   "[%s] %s: %lld commands never applied, %lld applied twice or more so far\n",
                   bus_.options().instance.c_str(), e.instance.c_str(),
                   static_cast<long long>(e.skipped), static_cast<long long>(e.repeated));
    }
  }
}

void MonitorNode::OnSnapshot(const odonata::model_snapshot_t& m) {
  if (m.instance.empty()) return;
  const auto bytes = static_cast<std::size_t>(std::max(0, m.getEncodedSize()));
  if (bytes > kMaxSnapshotBytes) {
    ++bus_.stats().dropped;
    bus_.Report("oversize snapshot", "from '" + m.instance + "': " + std::to_string(bytes) +
                                         " bytes, over the cache's whole budget: not kept");
    return;
  }
  if (const auto it = snapshots_.find(m.instance); it != snapshots_.end()) {
    snapshot_bytes_ -= it->second.bytes;
    snapshots_.erase(it);
  }
  // The least recently heard go first, until the new one fits in count and in bytes.
  while (!snapshots_.empty() &&
         (snapshots_.size() >= kMaxSnapshots || snapshot_bytes_ + bytes > kMaxSnapshotBytes)) {
    const auto oldest = std::min_element(
        snapshots_.begin(), snapshots_.end(),
        [](const auto& a, const auto& b) { return a.second.received < b.second.received; });
    snapshot_bytes_ -= oldest->second.bytes;
    snapshots_.erase(oldest);
    ++bus_.stats().dropped;  // a snapshot forgotten to keep the bound (heartbeat: dropped)
  }
  snapshots_[m.instance] = CachedSnapshot{m, std::chrono::steady_clock::now(), bytes};
  snapshot_bytes_ += bytes;
}

void MonitorNode::OnControl(const odonata::control_t& m) {
  if (m.command == odonata::control_t::PUBLISH_SNAPSHOT) {
    // An identifier starting up asks for its last snapshot: answer from the cache.
    const auto it = snapshots_.find(m.target);
    if (it != snapshots_.end()) bus_.Publish(bus_.channels().model, it->second.snapshot);
    return;
  }
  if (!bus_.AcceptControl(m)) return;
  const auto params = [&] {
    return std::vector<std::pair<std::string, double>>{
        {"peers", static_cast<double>(peers_.peers().size())},
        {"snapshots_cached", static_cast<double>(snapshots_.size())},
        {"snapshot_bytes", static_cast<double>(snapshot_bytes_)}};
  };
  if (m.command == odonata::control_t::RESET) {
    std::fprintf(stderr, "[%s] reset by '%s': the scores so far are discarded\n",
                 bus_.options().instance.c_str(), m.sender.c_str());
    scores_.Reset();
    bus_.ReplyControl(m, true, "scores discarded", params());
  } else if (m.command == odonata::control_t::SHUTDOWN) {
    bus_.ReplyControl(m, true, "stopping (the summary is written on the way out)", params());
    bus_.Stop(0);
  } else if (m.command == odonata::control_t::GET) {
    bus_.ReplyControl(m, true, "parameters in force", params());
  } else {
    bus_.RejectUnsupported(m);
  }
}

void MonitorNode::CheckPeers() {
  const auto silent =
      peers_.CheckSilence(std::chrono::steady_clock::now(), options_.heartbeat_timeout_s);
  for (const auto& e : silent) {
    std::fprintf(stderr, "[%s] WARNING: %s (%s) silent for %.1f s (last state %s)\n",
                 bus_.options().instance.c_str(), e.instance.c_str(), e.service.c_str(), e.silent_s,
                 e.state.c_str());
  }
}

void MonitorNode::PublishAccuracy() {
  const auto& order = scores_.outputs();
  if (order.empty()) return;
  odonata::accuracy_t a;
  a.utime = bus::NowUtime();
  a.seq = accuracy_seq_++;
  a.last_sample = scores_.last_sample();
  a.gaps = scores_.gaps();
  a.num_outputs = static_cast<int32_t>(order.size());
  a.names = order;
  a.window_samples = 0;
  a.total_samples = 0;
  const auto append = [](const auto& score, std::vector<double>* fit, std::vector<double>* vaf,
                         std::vector<double>* rmse) {
    fit->push_back(score.fit_percent);
    vaf->push_back(score.vaf_percent);
    rmse->push_back(score.rmse);
  };
  a.horizon = 0;
  for (const auto& name : order) {
    const auto& o = scores_.output(name);
    a.window_samples = static_cast<int32_t>(o.fuzzy.one_step.window.size());
    a.total_samples = o.fuzzy.one_step.total.samples();
    append(o.fuzzy.one_step.window.Get(), &a.window_fit_one_step, &a.window_vaf_one_step,
           &a.window_rmse_one_step);
    append(o.fuzzy.one_step.total.Get(), &a.total_fit_one_step, &a.total_vaf_one_step,
           &a.total_rmse_one_step);
    append(o.fuzzy.free_run.window.Get(), &a.window_fit_free_run, &a.window_vaf_free_run,
           &a.window_rmse_free_run);
    append(o.fuzzy.free_run.total.Get(), &a.total_fit_free_run, &a.total_vaf_free_run,
           &a.total_rmse_free_run);
    a.rules.push_back(o.rules);
    // NaN where the predictions carry no such score (no baseline, no horizon).
    const auto fit = [](const monitoring::ModeScore& score, bool window) {
      if (!score.scored()) return std::nan("");
      return (window ? score.window.Get() : score.total.Get()).fit_percent;
    };
    a.window_fit_one_step_arx.push_back(fit(o.arx.one_step, true));
    a.total_fit_one_step_arx.push_back(fit(o.arx.one_step, false));
    a.window_fit_free_run_arx.push_back(fit(o.arx.free_run, true));
    a.total_fit_free_run_arx.push_back(fit(o.arx.free_run, false));
    if (o.has_ahead()) a.horizon = o.horizon;
    a.window_fit_ahead.push_back(fit(o.fuzzy.ahead, true));
    a.total_fit_ahead.push_back(fit(o.fuzzy.ahead, false));
    a.window_fit_ahead_arx.push_back(fit(o.arx.ahead, true));
    a.total_fit_ahead_arx.push_back(fit(o.arx.ahead, false));
  }
  bus_.Publish(bus_.channels().accuracy, a);
}

nlohmann::json MonitorNode::Summary() const {
  nlohmann::json j = scores_.Summary();
  if (!peers_.peers().empty()) j["services"] = peers_.Summary();
  return j;
}

void MonitorNode::Print() {
  std::string text;
  char line[320];
  // One row per mode, fuzzy beside the live ARX over the window and since the run began, so the
  // table fits an 80-column terminal: one step ahead, K steps ahead with a horizon (loops that
  // integrate), and free run. "<= ARX" marks a mode whose rules do not beat linear over the
  // window (one step or K steps ahead: the comparison the alarm makes; free run where ARX's own
  // simulation holds: two diverging runs say nothing).
  std::snprintf(line, sizeof line, "%-9s %5s %-8s %19s %19s %6s\n", "output", "rules", "mode",
                "FIT window (ARX)", "FIT run (ARX)", "samples");
  text += line;
  // A FIT below −100 % (errors over twice the signal's spread) is a diverging simulation, not
  // a figure to read digits from: "diverges", as every tool prints it (metrics/accuracy.hpp).
  const auto fit_text = [](double fit) {
    char cell[24];
    if (metrics::FitDiverges(fit))
      std::snprintf(cell, sizeof cell, "%8s", "diverges");
    else
      std::snprintf(cell, sizeof cell, "%8.2f", fit);
    return std::string(cell);
  };
  const auto pair = [&fit_text](double fuzzy, double arx, bool has_arx) {
    return fit_text(fuzzy) + " (" + (has_arx ? fit_text(arx) : std::string(7, ' ') + "-") + ")";
  };
  for (const auto& name : scores_.outputs()) {
    const auto& o = scores_.output(name);
    const bool arx = o.has_arx();
    const bool k_step = o.has_ahead();
    // A name longer than its column goes on a line of its own, so the columns stay aligned.
    std::string label_text = name;
    if (name.size() > 9) {
      text += name + "\n";
      label_text = "";
    }
    const auto row = [&](bool first, const std::string& mode, const monitoring::ModeScore& mine,
                         const monitoring::ModeScore& linear, bool behind,
                         const std::string& note = "") {
      const std::string label = first ? label_text : "";
      const std::string rules = first ? std::to_string(o.rules) : "";
      const std::string samples = first ? std::to_string(mine.total.samples()) : "";
      std::snprintf(
          line, sizeof line, "%-9s %5s %-8s %19s %19s %6s%s\n", label.c_str(), rules.c_str(),
          mode.c_str(),
          pair(mine.window.Get().fit_percent, linear.window.Get().fit_percent, arx).c_str(),
          pair(mine.total.Get().fit_percent, linear.total.Get().fit_percent, arx).c_str(),
          samples.c_str(), (std::string(behind ? "  <= ARX" : "") + note).c_str());
      text += line;
    };
    const bool behind = scores_.BehindArx(name);
    // How often the samples lay outside the model's data (it predicted them partly linearly).
    const long scored = o.fuzzy.one_step.total.samples();
    const std::string outside =
        o.outside > 0 && scored > 0
            ? "  " + std::to_string((100 * o.outside + scored / 2) / scored) + "% outside"
            : "";
    row(true, "1 step", o.fuzzy.one_step, o.arx.one_step, behind && !k_step, outside);
    if (k_step)
      row(false, std::to_string(o.horizon) + " steps", o.fuzzy.ahead, o.arx.ahead, behind);
    const double free = o.fuzzy.free_run.window.Get().fit_percent;
    const double arx_free = o.arx.free_run.window.Get().fit_percent;
    row(false, "free run", o.fuzzy.free_run, o.arx.free_run,
        arx && !metrics::FitDiverges(arx_free) && free <= arx_free);
    // The identifier's intervals: how often the measurement fell within them, and how wide.
    if (o.one_step_interval.scored > 0) {
      const auto tally = [](const char* mode, const metrics::IntervalTally& t) {
        char cell[80];
        std::snprintf(cell, sizeof cell, "%s in %.1f%% (width %.3g)", mode, 100.0 * t.coverage(),
                      t.mean_width());
        return std::string(cell);
      };
      std::string s = tally("1 step", o.one_step_interval);
      if (o.ahead_interval.scored > 0)
        s += ", " + tally((std::to_string(o.horizon) + " steps").c_str(), o.ahead_interval);
      if (o.free_run_interval.scored > 0) s += ", " + tally("free run", o.free_run_interval);
      std::snprintf(line, sizeof line, "%-9s %.0f%% interval: %s\n", "", 100.0 * o.interval_level,
                    s.c_str());
      text += line;
    }
  }
  for (const auto& [instance, peer] : peers_.peers()) {
    const monitoring::Heartbeat& p = peer.last;
    std::snprintf(line, sizeof line,
                  "  %-20s %-9s errors %lld, dropped %lld, gaps %lld, skipped %lld, repeated "
                  "%lld%s\n",
                  instance.c_str(), p.state.c_str(), static_cast<long long>(p.decode_errors),
                  static_cast<long long>(p.dropped), static_cast<long long>(p.gaps),
                  static_cast<long long>(p.skipped), static_cast<long long>(p.repeated),
                  peer.silent ? "  SILENT" : "");
    text += line;
    // The identifier's "seen enough" (one line per output), under its own row.
    std::size_t from = 0;
    while (from < p.detail.size()) {
      const std::size_t end = std::min(p.detail.find('\n', from), p.detail.size());
      text += "    " + p.detail.substr(from, end - from) + "\n";
      from = end + 1;
    }
  }
  if (options_.live_table) {
    // Move up over the previous table and redraw it in place. A line wider than the terminal
    // would wrap and the move up would miss it (the table crept down the screen): each line is
    // cut to the terminal's width.
    text = ClipLines(text, TerminalColumns());
    if (printed_lines_ > 0) std::printf("\033[%zuA\033[J", printed_lines_);
    std::fputs(text.c_str(), stdout);
    printed_lines_ = static_cast<std::size_t>(std::count(text.begin(), text.end(), '\n'));
  } else if (!scores_.outputs().empty()) {
    std::fputs(text.c_str(), stdout);
  }
  std::fflush(stdout);
}

}  // namespace odonata::monitor

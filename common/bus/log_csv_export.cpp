#include "bus/log_csv_export.hpp"

#include <map>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "bus/event_log_reader.hpp"
#include "bus/model_snapshot_codec.hpp"
#include "bus/safe_decode.hpp"
#include "bus/sample_fields.hpp"

#include <cmath>
#include <fstream>
#include <functional>

#include <nlohmann/json.hpp>
#include "io/csv_writer.hpp"
#include "io/row_decimator.hpp"
#include "odonata/beat_state_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/prediction_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace odonata::bus {
namespace {

struct Run {
  std::map<int64_t, odonata::plant_state_t> states;     // by seq, first copy kept
  std::map<int64_t, odonata::wing_command_t> commands;  // by seq, first copy kept
  std::map<int64_t, odonata::beat_state_t> beats;       // by seq, first copy kept
};

}  // namespace

ExportSummary ExportLogToCsv(const std::vector<std::string>& log_paths, const std::string& csv_path,
                             const ExportOptions& options) {
  ExportSummary summary;
  std::vector<Run> runs(1);
  ForEachLogEvent(log_paths, [&](const lcm::LogEvent& ev) {
    if (ev.channel == options.state_channel) {
      odonata::plant_state_t s;
      if (!SafeDecode(&s, ev.data, ev.datalen) || !AllFinite(s)) {
        ++summary.undecodable;
        return;
      }
      // A fresh initial state after others marks a plant reset: a new run.
      if (s.seq == 0 && s.command_seq < 0 && !runs.back().states.empty() &&
          (runs.back().states.size() > 1 || !runs.back().commands.empty())) {
        runs.emplace_back();
      }
      runs.back().states.emplace(s.seq, s);
    } else if (ev.channel == options.command_channel) {
      odonata::wing_command_t c;
      if (!SafeDecode(&c, ev.data, ev.datalen) || !AllFinite(c) || !CountProblems(c).empty()) {
        ++summary.undecodable;
        return;
      }
      runs.back().commands.emplace(c.seq, c);
    } else if (ev.channel == options.beat_state_channel) {
      odonata::beat_state_t b;
      if (!SafeDecode(&b, ev.data, ev.datalen) || !AllFinite(b)) {
        ++summary.undecodable;
        return;
      }
      runs.back().beats.emplace(b.seq, b);
    }
  });
  summary.runs = static_cast<int>(runs.size());
  // Negative indices count from the end (−1 the last run), as a real-time plant that idled
  // before its reset adds a run of its own at the start.
  const int pick = options.run < 0 ? summary.runs + options.run : options.run;
  if (pick < 0 || pick >= summary.runs) {
    throw std::runtime_error("the log has " + std::to_string(summary.runs) + " run(s); no run " +
                             std::to_string(pick));
  }
  summary.exported_run = pick;
  const Run& run = runs[static_cast<std::size_t>(pick)];
  if (run.commands.empty())
    throw std::runtime_error("no commands on " + options.command_channel + " in the log");

  const auto& first_command = run.commands.begin()->second;
  std::vector<std::string> header{"t_s"};
  for (const auto& n : CommandFieldNames()) header.push_back(n);
  for (const auto& n : StateFieldNames()) header.push_back(n);
  for (const auto& n : first_command.excitation_names) header.push_back(n);
  summary.beat_columns = !run.beats.empty();
  if (summary.beat_columns) {
    for (const auto& n : BeatFieldNames()) header.push_back(n);
    for (const auto& n : AppliedFieldNames()) header.push_back(n);
  }
  io::CsvWriter out(csv_path, header);
  std::vector<bool> is_input;
  for (const auto& n : header) is_input.push_back(IsAveragedSignal(n));
  io::RowDecimator decimator(options.decimate, is_input);
  for (auto it = run.states.begin(); it != run.states.end(); ++it) {
    const auto next = run.states.find(it->first + 1);
    if (next == run.states.end()) {
      if (std::next(it) != run.states.end()) ++summary.incomplete;
      continue;
    }
    const auto cmd = run.commands.find(next->second.command_seq);
    if (cmd == run.commands.end() ||
        cmd->second.excitation_names != first_command.excitation_names) {
      ++summary.incomplete;
      continue;
    }
    std::vector<double> row{it->second.t_s};
    for (const auto& n : CommandFieldNames()) row.push_back(*CommandField(cmd->second, n));
    for (const auto& n : StateFieldNames()) row.push_back(*StateField(it->second, n));
    for (double v : cmd->second.excitations) row.push_back(v);
    if (summary.beat_columns) {
      // Averages up to t_k from beat state k; the command applied over [t_k, t_k+1) from beat
      // state k + 1, which answers the same command as state k + 1. The identifier pairs them
      // the same way (pipeline/sample_pairer.hpp).
      const auto beat = run.beats.find(it->first);
      const auto applied = run.beats.find(it->first + 1);
      if (beat == run.beats.end() || applied == run.beats.end() ||
          beat->second.command_seq != it->second.command_seq ||
          applied->second.command_seq != next->second.command_seq) {
        ++summary.incomplete;
        continue;
      }
      for (const auto& n : BeatFieldNames()) row.push_back(*BeatStateField(beat->second, n));
      for (const auto& n : AppliedFieldNames()) row.push_back(*BeatStateField(applied->second, n));
    }
    if (const auto block = decimator.Push(it->first, row)) {
      out.WriteRow(*block);
      ++summary.rows;
    }
  }
  out.Close();
  summary.dropped_blocks = decimator.dropped_blocks();
  if (summary.rows == 0)
    throw std::runtime_error("no complete samples in the log (states and commands never matched)");
  return summary;
}

namespace {
void ForEachEvent(const std::vector<std::string>& log_paths, const std::string& channel,
                  const std::function<void(const lcm::LogEvent&)>& fn) {
  ForEachLogEvent(log_paths, [&](const lcm::LogEvent& ev) {
    if (ev.channel == channel) fn(ev);
  });
}
}  // namespace

long ExportPredictionsToCsv(const std::vector<std::string>& log_paths, const std::string& channel,
                            const std::string& csv_path) {
  std::vector<odonata::prediction_t> all;
  ForEachEvent(log_paths, channel, [&all](const lcm::LogEvent& ev) {
    odonata::prediction_t p;
    if (!SafeDecode(&p, ev.data, ev.datalen) || p.num_outputs <= 0) return;
    const auto n = static_cast<std::size_t>(p.num_outputs);
    if (p.names.size() != n || p.measured.size() != n || p.predicted.size() != n ||
        p.free_run.size() != n || p.next.size() != n || p.rules.size() != n ||
        p.max_entropy.size() != n)
      return;
    if (!all.empty() && p.names != all.front().names) return;
    all.push_back(std::move(p));
  });
  if (all.empty()) throw std::runtime_error("no predictions on " + channel + " in the log");
  std::vector<std::string> header{"run", "sample", "learning"};
  for (const auto& name : all.front().names)
    for (const char* f :
         {"_measured", "_predicted", "_free_run", "_next", "_rules", "_max_entropy"})
      header.push_back(name + f);
  io::CsvWriter out(csv_path, header);
  int run = 0;
  int64_t last = -1;
  long rows = 0;
  for (const auto& p : all) {
    if (p.sample <= last) ++run;
    last = p.sample;
    std::vector<double> row{double(run), double(p.sample), double(p.learning)};
    for (std::size_t o = 0; o < p.names.size(); ++o) {
      // NaN (no forecast with delay 0) is written as the last finite value would mislead; the
      // CSV reader rejects NaN, so write the prediction itself instead.
      const double next = std::isfinite(p.next[o]) ? p.next[o] : p.predicted[o];
      for (double v : {p.measured[o], p.predicted[o], p.free_run[o], next, double(p.rules[o]),
                       p.max_entropy[o]})
        row.push_back(v);
    }
    out.WriteRow(row);
    ++rows;
  }
  out.Close();
  return rows;
}

long ExportSnapshotsToJson(const std::vector<std::string>& log_paths, const std::string& channel,
                           const std::string& json_path) {
  nlohmann::json arr = nlohmann::json::array();
  ForEachEvent(log_paths, channel, [&arr](const lcm::LogEvent& ev) {
    odonata::model_snapshot_t m;
    if (!SafeDecode(&m, ev.data, ev.datalen)) return;
    try {
      arr.push_back({{"utime", m.utime},
                     {"samples_learned", m.samples_learned},
                     {"instance", m.instance},
                     {"model", DecodeSnapshot(m).ToJson()}});
    } catch (const std::exception&) {
      // a snapshot that does not describe a valid model is skipped
    }
  });
  std::ofstream out(json_path);
  out << arr.dump() << "\n";
  if (!out) throw std::runtime_error(json_path + ": cannot write");
  return static_cast<long>(arr.size());
}

}  // namespace odonata::bus

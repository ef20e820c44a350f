#include "bus/log_csv_export.hpp"

#include <map>
#include <stdexcept>

#include <lcm/lcm-cpp.hpp>

#include "bus/sample_fields.hpp"
#include "io/csv_writer.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace odonata::bus {
namespace {

struct Run {
  std::map<int64_t, odonata::plant_state_t> states;     // by seq, first copy kept
  std::map<int64_t, odonata::wing_command_t> commands;  // by seq, first copy kept
};

}  // namespace

ExportSummary ExportLogToCsv(const std::vector<std::string>& log_paths, const std::string& csv_path,
                             const ExportOptions& options) {
  ExportSummary summary;
  std::vector<Run> runs(1);
  for (const auto& path : log_paths) {
    lcm::LogFile log(path, "r");
    if (!log.good()) throw std::runtime_error(path + ": cannot open event log");
    while (const lcm::LogEvent* ev = log.readNextEvent()) {
      if (ev->channel == options.state_channel) {
        odonata::plant_state_t s;
        if (s.decode(ev->data, 0, ev->datalen) < 0 || !AllFinite(s)) {
          ++summary.undecodable;
          continue;
        }
        // A fresh initial state after others marks a plant reset: a new run.
        if (s.seq == 0 && s.command_seq < 0 && !runs.back().states.empty() &&
            (runs.back().states.size() > 1 || !runs.back().commands.empty())) {
          runs.emplace_back();
        }
        runs.back().states.emplace(s.seq, s);
      } else if (ev->channel == options.command_channel) {
        odonata::wing_command_t c;
        if (c.decode(ev->data, 0, ev->datalen) < 0 || !AllFinite(c) || !CountProblems(c).empty()) {
          ++summary.undecodable;
          continue;
        }
        runs.back().commands.emplace(c.seq, c);
      }
    }
  }
  summary.runs = static_cast<int>(runs.size());
  const int pick = options.run < 0 ? summary.runs - 1 : options.run;
  if (pick >= summary.runs) {
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
  io::CsvWriter out(csv_path, header);
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
    out.WriteRow(row);
    ++summary.rows;
  }
  out.Close();
  if (summary.rows == 0)
    throw std::runtime_error("no complete samples in the log (states and commands never matched)");
  return summary;
}

}  // namespace odonata::bus

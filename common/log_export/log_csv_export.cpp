#include "log_export/log_csv_export.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <optional>
#include <stdexcept>
#include <variant>

#include <lcm/lcm-cpp.hpp>
#include <nlohmann/json.hpp>

#include "bus/event_log_reader.hpp"
#include "bus/safe_decode.hpp"
#include "experiments/sample_columns.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_writer.hpp"
#include "io/row_decimator.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/paired_sample.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/signals_message.hpp"
#include "messages/wing_command_message.hpp"
#include "model_messages/model_snapshot_message.hpp"
#include "monitoring/prediction_from_message.hpp"
#include "odonata/prediction_t.hpp"
#include "sequence/sample_sequence.hpp"

namespace odonata::log_export {
namespace {

using bus::SafeDecode;
using Message =
    std::variant<odonata::plant_state_t, odonata::wing_command_t, odonata::beat_state_t>;

// What the first pass learns of one run.
struct RunFacts {
  long beats = 0;  // beat states logged while it ran
  // Its first sample's (paired without beat states): none when no state of it answers a command.
  std::optional<odonata::wing_command_t> first_command;
};

// Replays the logged messages, in order, through one pairer as the identifier's (restarts
// included). A run is what lies between its restarts: a fresh state 0 after others starts one
// only once the plant confirms it (pipeline/sample_pairer.hpp), so a stale or forged state 0 does
// not cut a run in two, nor does a repeat of state 0 that a busy lockstep plant sent before it
// read command 0 and that was logged after it. on_message(run, message, rejected) follows each
// message (the run it left the pairer in; rejected: the pairing rules said no), on_event(run,
// event) each sample or gap.
void Replay(const std::vector<Message>& messages, const pipeline::PairingNeeds& needs,
            const std::function<void(int, const Message&, bool)>& on_message,
            const std::function<void(int, const messages::PairedMessages&)>& on_event) {
  messages::MessagePairer pairer(needs);
  int run = 0;
  const auto handle = [&](const std::vector<messages::PairedMessages>& events) {
    for (const auto& e : events) {
      if (e.kind == messages::PairedMessages::Kind::kRestart) {
        ++run;
      } else {
        on_event(run, e);
      }
    }
  };
  for (const Message& m : messages) {
    std::vector<messages::PairedMessages> events;
    bool rejected = false;
    try {
      events = std::visit(
          [&](const auto& msg) {
            using T = std::decay_t<decltype(msg)>;
            if constexpr (std::is_same_v<T, odonata::plant_state_t>) {
              return pairer.OnState(msg);
            } else if constexpr (std::is_same_v<T, odonata::wing_command_t>) {
              return pairer.OnCommand(msg);
            } else {
              return pairer.OnBeat(msg);
            }
          },
          m);
    } catch (const std::invalid_argument&) {
      rejected = true;  // out of order, a leap, or a second command
    }
    handle(events);
    on_message(run, m, rejected);
  }
  handle(pairer.Finish());
}

}  // namespace

ExportSummary ExportLogToCsv(const std::vector<std::string>& log_paths, const std::string& csv_path,
                             const ExportOptions& options) {
  ExportSummary summary;
  std::vector<Message> messages;
  long commands = 0;
  bus::ForEachLogEvent(log_paths, [&](const lcm::LogEvent& ev) {
    if (ev.channel == options.state_channel) {
      odonata::plant_state_t s;
      if (!SafeDecode(&s, ev.data, ev.datalen) || !messages::AllFinite(s)) {
        ++summary.undecodable;
        return;
      }
      messages.emplace_back(std::move(s));
    } else if (ev.channel == options.command_channel) {
      odonata::wing_command_t c;
      if (!SafeDecode(&c, ev.data, ev.datalen) || !messages::AllFinite(c) ||
          !messages::CountProblems(c).empty()) {
        ++summary.undecodable;
        return;
      }
      ++commands;
      messages.emplace_back(std::move(c));
    } else if (ev.channel == options.beat_state_channel) {
      odonata::beat_state_t b;
      if (!SafeDecode(&b, ev.data, ev.datalen) || !messages::AllFinite(b)) {
        ++summary.undecodable;
        return;
      }
      messages.emplace_back(std::move(b));
    }
  });
  if (commands == 0)
    throw std::runtime_error("no commands on " + options.command_channel +
                             " in the log: it holds no simulated DI-MAV run; a vehicle's "
                             "signals (signals_t) export with --signals");

  // First pass: the runs, and what each needs for its header and its pairing.
  std::vector<RunFacts> runs(1);
  const auto facts = [&](int run) -> RunFacts& {
    if (static_cast<std::size_t>(run) >= runs.size())
      runs.resize(static_cast<std::size_t>(run) + 1);
    return runs[static_cast<std::size_t>(run)];
  };
  Replay(
      messages, pipeline::PairingNeeds{},
      [&](int run, const Message& m, bool) {
        RunFacts& f = facts(run);  // a run of states alone counts too
        if (std::holds_alternative<odonata::beat_state_t>(m)) ++f.beats;
      },
      [&](int run, const messages::PairedMessages& e) {
        RunFacts& f = facts(run);
        if (e.kind == messages::PairedMessages::Kind::kSample && !f.first_command)
          f.first_command = e.command;
      });
  summary.runs = static_cast<int>(runs.size());
  // Negative indices count from the end (−1 the last run), as a real-time plant that idled
  // before its reset adds a run of its own at the start; they count only the runs that hold
  // samples, so a plant reset twice (a RESET resent over a lossy link) or restarted after the
  // last command, which opens a run of states alone, does not shift them.
  int pick = options.run < 0 ? summary.runs + options.run : options.run;
  if (options.run < 0) {
    int from_end = -options.run;
    pick = -1;
    for (int r = summary.runs - 1; r >= 0 && pick < 0; --r)
      if (runs[static_cast<std::size_t>(r)].first_command && --from_end == 0) pick = r;
    if (pick < 0)
      throw std::runtime_error("the log has " + std::to_string(summary.runs) +
                               " run(s), fewer than " + std::to_string(-options.run) +
                               " with samples; no run " + std::to_string(options.run));
  }
  if (pick < 0 || pick >= summary.runs) {
    throw std::runtime_error("the log has " + std::to_string(summary.runs) + " run(s); no run " +
                             std::to_string(pick));
  }
  summary.exported_run = pick;
  const RunFacts& run = runs[static_cast<std::size_t>(pick)];
  if (!run.first_command) {
    // A plant restarted after the last command opens a run of states alone: say which run to
    // take instead of only that no sample came.
    if (summary.runs > 1) {
      throw std::runtime_error("run " + std::to_string(pick) + " of " +
                               std::to_string(summary.runs) + " has no commands on " +
                               options.command_channel +
                               " that a state answers (a plant that started and was never "
                               "commanded); pick another with --run");
    }
    throw std::runtime_error("no complete samples in the log (states and commands never matched)");
  }
  const odonata::wing_command_t& first_command = *run.first_command;

  // The columns odonata-sim writes; the beat columns when the run has beat states.
  summary.beat_columns = run.beats > 0;
  const std::vector<std::string> header = experiments::SampleColumnNames(
      first_command.excitation_names, summary.beat_columns, summary.beat_columns);
  io::CsvWriter out(csv_path, header);
  std::vector<bool> is_input;
  for (const auto& n : header) is_input.push_back(experiments::IsAveragedSignal(n));
  io::RowDecimator decimator(options.decimate, is_input);

  // Second pass: row k is sample k of the run as the identifier pairs it
  // (messages/paired_sample.hpp).
  Replay(
      messages, pipeline::PairingNeeds{summary.beat_columns, summary.beat_columns},
      [&](int r, const Message&, bool rejected) {
        if (r == pick && rejected) ++summary.rejected;
      },
      [&](int r, const messages::PairedMessages& e) {
        if (r != pick) return;
        if (e.kind == messages::PairedMessages::Kind::kGap) summary.incomplete += e.lost;
        if (e.kind != messages::PairedMessages::Kind::kSample) return;
        if (e.command.excitation_names != first_command.excitation_names) {
          ++summary.incomplete;
          return;
        }
        std::vector<double> row;
        row.reserve(header.size());
        for (const auto& name : header) row.push_back(*messages::PairedSignal(e, name));
        if (const auto block = decimator.Push(e.index, row)) {
          out.WriteRow(*block);
          ++summary.rows;
        }
      });
  out.Close();
  summary.dropped_blocks = decimator.dropped_blocks();
  if (summary.rows == 0)
    throw std::runtime_error("no complete samples in the log (states and commands never matched)");
  return summary;
}

namespace {
void ForEachEvent(const std::vector<std::string>& log_paths, const std::string& channel,
                  const std::function<void(const lcm::LogEvent&)>& fn) {
  bus::ForEachLogEvent(log_paths, [&](const lcm::LogEvent& ev) {
    if (ev.channel == channel) fn(ev);
  });
}
}  // namespace

SignalsExportSummary ExportSignalsToCsv(const std::vector<std::string>& log_paths,
                                        const std::string& channel, const std::string& csv_path,
                                        int run) {
  SignalsExportSummary summary;
  // Runs, gaps and drops exactly as the identifier saw them, in the order they were logged.
  struct SignalsRun {
    std::vector<odonata::signals_t> samples;
    long lost = 0;
  };
  std::vector<SignalsRun> runs;
  pipeline::SampleSequence sequence;
  using Kind = pipeline::SampleSequence::Verdict::Kind;
  ForEachEvent(log_paths, channel, [&](const lcm::LogEvent& ev) {
    odonata::signals_t m;
    if (!SafeDecode(&m, ev.data, ev.datalen) || !messages::SignalsProblems(m).empty()) {
      ++summary.undecodable;
      return;
    }
    const auto verdict = sequence.Next(m.seq);
    if (verdict.kind == Kind::kDrop) {
      ++summary.dropped;
      return;
    }
    if (runs.empty() || verdict.kind == Kind::kRestart) runs.emplace_back();
    runs.back().lost += verdict.lost;
    runs.back().samples.push_back(std::move(m));
  });
  if (runs.empty())
    throw std::runtime_error("no signals on " + channel + " in the log (" +
                             std::to_string(summary.undecodable) + " undecodable)");
  summary.runs = static_cast<int>(runs.size());
  const int index = run < 0 ? summary.runs + run : run;
  if (index < 0 || index >= summary.runs)
    throw std::runtime_error("no run " + std::to_string(run) + ": the log holds " +
                             std::to_string(summary.runs));
  summary.exported_run = index;
  const SignalsRun& chosen = runs[static_cast<std::size_t>(index)];
  summary.lost = chosen.lost;
  const auto& first = chosen.samples.front();
  std::vector<std::string> header{"seq", "t_s"};
  for (const std::string& name : first.names) {
    // A vehicle that publishes its own t_s (or seq) must still export a file odonata-fit reads.
    std::string column = name;
    for (int k = 1; std::find(header.begin(), header.end(), column) != header.end(); ++k)
      column = name + "_vehicle" + (k > 1 ? std::to_string(k) : "");
    if (column != name) {
      summary.renamed.emplace_back(name, column);
    }
    header.push_back(column);
  }
  io::CsvWriter out(csv_path, header);
  for (const auto& m : chosen.samples) {
    if (m.names != first.names) {
      ++summary.foreign;
      continue;
    }
    // In doubles (exact for any utime of this era): a forged utime must not overflow an int64.
    std::vector<double> row{static_cast<double>(m.seq), 1e-6 * (static_cast<double>(m.utime) -
                                                                static_cast<double>(first.utime))};
    row.insert(row.end(), m.values.begin(), m.values.end());
    out.WriteRow(row);
    ++summary.rows;
  }
  out.Close();
  return summary;
}

long ExportPredictionsToCsv(const std::vector<std::string>& log_paths, const std::string& channel,
                            const std::string& csv_path) {
  std::vector<odonata::prediction_t> all;
  ForEachEvent(log_paths, channel, [&all](const lcm::LogEvent& ev) {
    odonata::prediction_t p;
    if (!SafeDecode(&p, ev.data, ev.datalen) || p.num_outputs <= 0) return;
    const auto n = static_cast<std::size_t>(p.num_outputs);
    if (p.names.size() != n || p.measured.size() != n || p.predicted.size() != n ||
        p.free_run.size() != n || p.next.size() != n || p.rules.size() != n ||
        p.max_entropy.size() != n || p.arx_predicted.size() != n || p.arx_free_run.size() != n)
      return;
    if (!all.empty() && p.names != all.front().names) return;
    all.push_back(std::move(p));
  });
  if (all.empty()) throw std::runtime_error("no predictions on " + channel + " in the log");
  // K-step columns when every prediction carries them with one horizon (a CSV has no empty
  // cells for the ones that do not).
  const int horizon = all.front().horizon;
  const bool ahead = horizon > 1 && std::all_of(all.begin(), all.end(), [&](const auto& p) {
                       return p.horizon == horizon && p.ahead.size() == p.names.size() &&
                              p.arx_ahead.size() == p.names.size();
                     });
  // The identifier's interval half widths (−1: not known yet), likewise when every prediction
  // carries them.
  const bool widths = std::all_of(all.begin(), all.end(), [&](const auto& p) {
    return p.half_width.size() == p.names.size() &&
           (!ahead || p.ahead_half_width.size() == p.names.size());
  });
  const bool free_widths = std::all_of(all.begin(), all.end(), [&](const auto& p) {
    return p.free_run_half_width.size() == p.names.size();
  });
  // Has the model seen enough (0 short of excitation, 1 still learning, 2 settled), likewise.
  const bool seen = std::all_of(all.begin(), all.end(), [&](const auto& p) {
    return p.seen_enough.size() == p.names.size();
  });
  std::vector<std::string> header{"run", "sample", "learning"};
  for (const auto& name : all.front().names) {
    for (const char* f : {"_measured", "_predicted", "_free_run", "_next", "_rules", "_max_entropy",
                          "_arx_predicted", "_arx_free_run"})
      header.push_back(name + f);
    if (ahead) {
      header.push_back(name + "_ahead_" + std::to_string(horizon));
      header.push_back(name + "_arx_ahead_" + std::to_string(horizon));
    }
    if (widths) header.push_back(name + "_half_width");
    if (widths && ahead) header.push_back(name + "_ahead_half_width_" + std::to_string(horizon));
    if (free_widths) header.push_back(name + "_free_run_half_width");
    if (seen) header.push_back(name + "_seen_enough");
  }
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
                       p.max_entropy[o], p.arx_predicted[o], p.arx_free_run[o]})
        row.push_back(v);
      if (ahead) {
        row.push_back(p.ahead[o]);
        row.push_back(p.arx_ahead[o]);
      }
      if (widths) row.push_back(p.half_width[o]);
      if (widths && ahead) row.push_back(p.ahead_half_width[o]);
      if (free_widths) row.push_back(p.free_run_half_width[o]);
      if (seen) row.push_back(double(p.seen_enough[o]));
    }
    out.WriteRow(row);
    ++rows;
  }
  out.Close();
  return rows;
}

long ScorePredictionsToJson(const std::vector<std::string>& log_paths, const std::string& channel,
                            const std::string& json_path, int64_t* missing_out) {
  monitoring::PredictionScoreboard board(monitoring::ScoreboardOptions{});
  long scored = 0;
  // Predictions the identifier published that the log lacks: gaps in its message counter (a
  // counter that goes back is a restarted identifier, counting afresh).
  int64_t missing = 0, last_seq = -1;
  ForEachEvent(log_paths, channel, [&](const lcm::LogEvent& ev) {
    odonata::prediction_t p;
    if (!SafeDecode(&p, ev.data, ev.datalen) || p.num_outputs <= 0) return;
    if (last_seq >= 0 && p.seq > last_seq + 1) missing += p.seq - last_seq - 1;
    if (p.seq >= 0) last_seq = p.seq;
    try {
      board.Add(monitoring::PredictionFromMessage(p));
      ++scored;
    } catch (const std::invalid_argument&) {
      // a prediction the monitor would drop too (ragged, NaN, a duplicate or a leap)
    }
  });
  if (scored == 0) throw std::runtime_error("no predictions on " + channel + " in the log");
  nlohmann::json summary = board.Summary();
  summary["predictions_missing"] = missing;
  io::WriteFileAtomically(json_path, summary.dump(1) + "\n");
  if (missing_out != nullptr) *missing_out = missing;
  return scored;
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
                     {"model", model_messages::DecodeSnapshot(m).ToJson()}});
    } catch (const std::exception&) {
      // a snapshot that does not describe a valid model is skipped
    }
  });
  io::WriteFileAtomically(json_path, arr.dump() + "\n");
  return static_cast<long>(arr.size());
}

}  // namespace odonata::log_export

// odonata-logger: records LCM channels into standard event logs, and exports a log to the CSV
// that odonata-fit reads.

#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include "bus/event_log_reader.hpp"
#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "io/atomic_file.hpp"
#include "log_export/log_csv_export.hpp"
#include "logger_node.hpp"

namespace {

// `record`'s options: the node's, the bus's, and the sizes given in MB and kB.
struct RecordCli {
  odonata::logger::RecordOptions rec;
  odonata::cli::BusCliOptions bus;
  double split_mb = 0, max_mb = 0, max_event_kb = 0;
};

// `export`'s options.
struct ExportCli {
  std::vector<std::string> logs;
  std::string csv;
  odonata::log_export::ExportOptions ex;
  bool signals = false, strict = false;
  std::string signals_channel = "VEHICLE_SIGNALS";
  std::string predictions_csv, snapshots_json, scores_json;
  std::string prediction_channel = "ODONATA_PREDICTION", model_channel = "ODONATA_MODEL";
};

CLI::App* AddRecordCommand(CLI::App& app, RecordCli& r) {
  r.bus.instance = "logger";
  auto* record = app.add_subcommand("record", "record channels until SIGINT/SIGTERM");
  record
      ->add_option("--output,-o", r.rec.prefix,
                   "file prefix: files PREFIX.00000, …, numbered on after any already there "
                   "(never overwritten); missing directories are created")
      ->required();
  record->add_option("--channels", r.rec.channels_regex, "channel regex")->capture_default_str();
  record->add_option("--split-mb", r.split_mb, "start a new file past this many MB (0: never)")
      ->check(CLI::NonNegativeNumber);
  record
      ->add_option("--max-mb", r.max_mb,
                   "disk budget: stop writing once the recording's files hold this many MB "
                   "(0: no limit); what is refused is counted as dropped in the heartbeat")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  record
      ->add_option("--max-event-kb", r.max_event_kb,
                   "do not write a message larger than this many kB (0: no limit): a flood of "
                   "forged large messages cannot fill the disk; counted as dropped")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  record->add_option("--flush-period", r.rec.flush_period_s, "seconds between flushes to disk")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  odonata::cli::AddBusOptions(record, &r.bus, {"instance name in heartbeats"});
  return record;
}

CLI::App* AddExportCommand(CLI::App& app, ExportCli& e) {
  auto* exp = app.add_subcommand("export", "write a recorded log as CSV for odonata-fit");
  exp->add_option("logs", e.logs, "event log file(s), oldest first")
      ->required()
      ->check(CLI::ExistingFile);
  exp->add_option("--output,-o", e.csv, "CSV file to write")->required();
  exp->add_option("--command-channel", e.ex.command_channel)->capture_default_str();
  exp->add_option("--state-channel", e.ex.state_channel)->capture_default_str();
  exp->add_option("--beat-state-channel", e.ex.beat_state_channel,
                  "beat averages and applied command (columns *_avg, *_applied_rad when present)")
      ->capture_default_str();
  exp->add_flag("--signals", e.signals,
                "export any vehicle's signals_t samples (columns seq, t_s and its signals) instead "
                "of the DI-MAV's commands and states");
  exp->add_option("--signals-channel", e.signals_channel, "channel of --signals")
      ->capture_default_str();
  exp->add_option("--predictions", e.predictions_csv, "also write ODONATA_PREDICTION as CSV here");
  exp->add_option("--snapshots", e.snapshots_json,
                  "also write ODONATA_MODEL snapshots as JSON here");
  exp->add_option(
      "--scores", e.scores_json,
      "also score the logged predictions as odonata-monitor does (one-step and free-run "
      "accuracy per output, run by run) and write them as JSON here");
  exp->add_option("--prediction-channel", e.prediction_channel)->capture_default_str();
  exp->add_option("--model-channel", e.model_channel)->capture_default_str();
  exp->add_option("--decimate", e.ex.decimate,
                  "one row per N samples, as odonata-sim --decimate (commands, excitations and "
                  "applied channels averaged over the block, the rest at its first sample)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  exp->add_flag("--strict", e.strict,
                "refuse a damaged log (a cut-off last event, garbage, an unreadable event): "
                "without it every readable event is exported and the bytes lost are counted in "
                "a warning");
  exp->add_option(
         "--run", e.ex.run,
         "run to export (a plant reset starts a new one); -1 = the last with samples, -2 the "
         "one before")
      ->capture_default_str();
  return exp;
}

// Returns the samples of the exported run the log misses (incomplete, or lost on the way): one
// count with the predictions missing, in the scores (ExportIdentifierOutputs).
long ExportSamples(const ExportCli& e) {
  if (e.signals) {
    if (e.ex.decimate != 1)
      throw std::runtime_error("--decimate applies to the DI-MAV's samples, not to --signals");
    const auto s =
        odonata::log_export::ExportSignalsToCsv(e.logs, e.signals_channel, e.csv, e.ex.run);
    std::fprintf(stderr,
                 "odonata-logger: %ld signals samples of run %d (of %d) written to %s; %ld lost, "
                 "%ld undecodable, %ld out of sequence, %ld with other signal names skipped\n",
                 s.rows, s.exported_run, s.runs, e.csv.c_str(), s.lost, s.undecodable, s.dropped,
                 s.foreign);
    for (const auto& [name, column] : s.renamed)
      std::fprintf(stderr,
                   "odonata-logger: the vehicle's signal '%s' is written as column '%s' (its "
                   "name is taken by an earlier column; give odonata-fit --output or --input "
                   "%s)\n",
                   name.c_str(), column.c_str(), column.c_str());
    return s.lost;
  }
  const auto s = odonata::log_export::ExportLogToCsv(e.logs, e.csv, e.ex);
  std::fprintf(stderr, "odonata-logger: %ld samples of run %d (of %d) written to %s", s.rows,
               s.exported_run, s.runs, e.csv.c_str());
  if (s.undecodable || s.incomplete || s.rejected)
    std::fprintf(stderr,
                 "; skipped %ld undecodable events, %ld incomplete samples and %ld messages "
                 "out of sequence",
                 s.undecodable, s.incomplete, s.rejected);
  if (s.dropped_blocks)
    std::fprintf(stderr, "; %ld decimation blocks dropped for a missing sample", s.dropped_blocks);
  std::fprintf(stderr, "\n");
  return s.incomplete;
}

// The identifier's predictions and snapshots in the log, as files and scores.
void ExportIdentifierOutputs(const ExportCli& e, long samples_missing) {
  if (!e.predictions_csv.empty()) {
    const long n = odonata::log_export::ExportPredictionsToCsv(e.logs, e.prediction_channel,
                                                               e.predictions_csv);
    std::fprintf(stderr, "odonata-logger: %ld predictions written to %s\n", n,
                 e.predictions_csv.c_str());
  }
  if (!e.scores_json.empty()) {
    int64_t missing = 0;
    const long n = odonata::log_export::ScorePredictionsToJson(e.logs, e.prediction_channel,
                                                               e.scores_json, &missing);
    std::fprintf(stderr, "odonata-logger: %ld predictions scored into %s\n", n,
                 e.scores_json.c_str());
    // The run's samples the log misses beside its predictions: what odonata-run counts as the
    // log's loss, one number whichever messages the logger happened to miss.
    std::ifstream in(e.scores_json);
    nlohmann::json scores = nlohmann::json::parse(in);
    scores["samples_missing"] = samples_missing;
    odonata::io::WriteFileAtomically(e.scores_json, scores.dump(1) + "\n");
    if (missing > 0)
      std::fprintf(stderr,
                   "odonata-logger: WARNING: %lld predictions the identifier published are "
                   "not in the log (lost on the way, or while the logger was down)\n",
                   static_cast<long long>(missing));
  }
  if (!e.snapshots_json.empty()) {
    const long n =
        odonata::log_export::ExportSnapshotsToJson(e.logs, e.model_channel, e.snapshots_json);
    std::fprintf(stderr, "odonata-logger: %ld model snapshots written to %s\n", n,
                 e.snapshots_json.c_str());
  }
}

int Record(RecordCli& r) {
  r.rec.split_bytes = static_cast<int64_t>(r.split_mb * 1e6);
  r.rec.max_bytes = static_cast<int64_t>(r.max_mb * 1e6);
  r.rec.max_event_bytes = static_cast<int64_t>(r.max_event_kb * 1e3);
  odonata::bus::BusNode bus(r.bus.ToBusOptions("odonata-logger"));
  odonata::logger::LoggerNode node(bus, r.rec);
  std::fprintf(stderr, "[%s] recording '%s' into %s", r.bus.instance.c_str(),
               r.rec.channels_regex.c_str(), node.writer().files().front().c_str());
  if (node.writer().earlier_files() > 0)
    std::fprintf(stderr, " (after %d earlier file(s) of this prefix, kept)",
                 node.writer().earlier_files());
  std::fprintf(stderr, "\n");
  return bus.Run();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Records LCM channels into event logs (lcm-logplayer and lcm-spy read them) and "
      "exports a log to CSV (odonata-sim's columns, for odonata-fit)."};
  app.require_subcommand(1);
  RecordCli r;
  ExportCli e;
  AddRecordCommand(app, r);
  const CLI::App* exp = AddExportCommand(app, e);
  // Any option can also come from a settings file (TOML/INI, option names as keys).
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  try {
    if (!*exp) return Record(r);
    if (e.strict)
      odonata::bus::ForEachLogEvent(
          e.logs, [](const lcm::LogEvent&) {}, true);
    ExportIdentifierOutputs(e, ExportSamples(e));
    return 0;
  } catch (const std::exception& ex) {
    std::fprintf(stderr, "odonata-logger: error: %s\n", ex.what());
    return 1;
  }
}

// odonata-logger: records LCM channels into standard event logs, and exports a log to the CSV
// that odonata-fit reads.

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/event_log_reader.hpp"
#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "log_export/log_csv_export.hpp"
#include "logger_node.hpp"

int main(int argc, char** argv) {
  CLI::App app{
      "Records LCM channels into event logs (lcm-logplayer and lcm-spy read them) and "
      "exports a log to CSV (odonata-sim's columns, for odonata-fit)."};
  app.require_subcommand(1);

  odonata::logger::RecordOptions rec;
  odonata::cli::BusCliOptions bus_options;
  bus_options.instance = "logger";
  double split_mb = 0;
  auto* record = app.add_subcommand("record", "record channels until SIGINT/SIGTERM");
  record
      ->add_option("--output,-o", rec.prefix,
                   "file prefix: files PREFIX.00000, …, numbered on after any already there "
                   "(never overwritten); missing directories are created")
      ->required();
  record->add_option("--channels", rec.channels_regex, "channel regex")->capture_default_str();
  record->add_option("--split-mb", split_mb, "start a new file past this many MB (0: never)")
      ->check(CLI::NonNegativeNumber);
  double max_mb = 0, max_event_kb = 0;
  record
      ->add_option("--max-mb", max_mb,
                   "disk budget: stop writing once the recording's files hold this many MB "
                   "(0: no limit); what is refused is counted as dropped in the heartbeat")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  record
      ->add_option("--max-event-kb", max_event_kb,
                   "do not write a message larger than this many kB (0: no limit): a flood of "
                   "forged large messages cannot fill the disk; counted as dropped")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  record->add_option("--flush-period", rec.flush_period_s, "seconds between flushes to disk")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  odonata::cli::AddBusOptions(record, &bus_options, {"instance name in heartbeats"});

  std::vector<std::string> logs;
  std::string csv;
  odonata::log_export::ExportOptions ex;
  auto* exp = app.add_subcommand("export", "write a recorded log as CSV for odonata-fit");
  exp->add_option("logs", logs, "event log file(s), oldest first")
      ->required()
      ->check(CLI::ExistingFile);
  exp->add_option("--output,-o", csv, "CSV file to write")->required();
  exp->add_option("--command-channel", ex.command_channel)->capture_default_str();
  exp->add_option("--state-channel", ex.state_channel)->capture_default_str();
  exp->add_option("--beat-state-channel", ex.beat_state_channel,
                  "beat averages and applied command (columns *_avg, *_applied_rad when present)")
      ->capture_default_str();
  bool signals = false;
  std::string signals_channel = "VEHICLE_SIGNALS";
  exp->add_flag("--signals", signals,
                "export any vehicle's signals_t samples (columns seq, t_s and its signals) instead "
                "of the DI-MAV's commands and states");
  exp->add_option("--signals-channel", signals_channel, "channel of --signals")
      ->capture_default_str();
  std::string predictions_csv, snapshots_json, scores_json;
  exp->add_option("--predictions", predictions_csv, "also write ODONATA_PREDICTION as CSV here");
  exp->add_option("--snapshots", snapshots_json, "also write ODONATA_MODEL snapshots as JSON here");
  exp->add_option(
      "--scores", scores_json,
      "also score the logged predictions as odonata-monitor does (one-step and free-run "
      "accuracy per output, run by run) and write them as JSON here");
  std::string prediction_channel = "ODONATA_PREDICTION", model_channel = "ODONATA_MODEL";
  exp->add_option("--prediction-channel", prediction_channel)->capture_default_str();
  exp->add_option("--model-channel", model_channel)->capture_default_str();
  exp->add_option("--decimate", ex.decimate,
                  "one row per N samples, as odonata-sim --decimate (commands, excitations and "
                  "applied channels averaged over the block, the rest at its first sample)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  bool strict = false;
  exp->add_flag("--strict", strict,
                "refuse a damaged log (a cut-off last event, garbage, an unreadable event): "
                "without it every readable event is exported and the bytes lost are counted in "
                "a warning");
  exp->add_option(
         "--run", ex.run,
         "run to export (a plant reset starts a new one); -1 = the last with samples, -2 the "
         "one before")
      ->capture_default_str();
  // Any option can also come from a settings file (TOML/INI, option names as keys).
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;

  try {
    if (*exp && strict)
      odonata::bus::ForEachLogEvent(
          logs, [](const lcm::LogEvent&) {}, true);
    if (*exp && signals) {
      if (ex.decimate != 1)
        throw std::runtime_error("--decimate applies to the DI-MAV's samples, not to --signals");
      const auto s = odonata::log_export::ExportSignalsToCsv(logs, signals_channel, csv, ex.run);
      std::fprintf(stderr,
                   "odonata-logger: %ld signals samples of run %d (of %d) written to %s; %ld lost, "
                   "%ld undecodable, %ld out of sequence, %ld with other signal names skipped\n",
                   s.rows, s.exported_run, s.runs, csv.c_str(), s.lost, s.undecodable, s.dropped,
                   s.foreign);
      for (const auto& [name, column] : s.renamed)
        std::fprintf(stderr,
                     "odonata-logger: the vehicle's signal '%s' is written as column '%s' (its "
                     "name is taken by an earlier column; give odonata-fit --output or --input "
                     "%s)\n",
                     name.c_str(), column.c_str(), column.c_str());
    }
    if (*exp && !signals) {
      const auto s = odonata::log_export::ExportLogToCsv(logs, csv, ex);
      std::fprintf(stderr, "odonata-logger: %ld samples of run %d (of %d) written to %s", s.rows,
                   s.exported_run, s.runs, csv.c_str());
      if (s.undecodable || s.incomplete || s.rejected)
        std::fprintf(stderr,
                     "; skipped %ld undecodable events, %ld incomplete samples and %ld messages "
                     "out of sequence",
                     s.undecodable, s.incomplete, s.rejected);
      if (s.dropped_blocks)
        std::fprintf(stderr, "; %ld decimation blocks dropped for a missing sample",
                     s.dropped_blocks);
      std::fprintf(stderr, "\n");
    }
    if (*exp) {
      if (!predictions_csv.empty()) {
        const long n =
            odonata::log_export::ExportPredictionsToCsv(logs, prediction_channel, predictions_csv);
        std::fprintf(stderr, "odonata-logger: %ld predictions written to %s\n", n,
                     predictions_csv.c_str());
      }
      if (!scores_json.empty()) {
        int64_t missing = 0;
        const long n = odonata::log_export::ScorePredictionsToJson(logs, prediction_channel,
                                                                   scores_json, &missing);
        std::fprintf(stderr, "odonata-logger: %ld predictions scored into %s\n", n,
                     scores_json.c_str());
        if (missing > 0)
          std::fprintf(stderr,
                       "odonata-logger: WARNING: %lld predictions the identifier published are "
                       "not in the log (lost on the way, or while the logger was down)\n",
                       static_cast<long long>(missing));
      }
      if (!snapshots_json.empty()) {
        const long n =
            odonata::log_export::ExportSnapshotsToJson(logs, model_channel, snapshots_json);
        std::fprintf(stderr, "odonata-logger: %ld model snapshots written to %s\n", n,
                     snapshots_json.c_str());
      }
      return 0;
    }
    rec.split_bytes = static_cast<int64_t>(split_mb * 1e6);
    rec.max_bytes = static_cast<int64_t>(max_mb * 1e6);
    rec.max_event_bytes = static_cast<int64_t>(max_event_kb * 1e3);
    odonata::bus::BusNode bus(bus_options.ToBusOptions("odonata-logger"));
    odonata::logger::LoggerNode node(bus, rec);
    std::fprintf(stderr, "[%s] recording '%s' into %s", bus_options.instance.c_str(),
                 rec.channels_regex.c_str(), node.writer().files().front().c_str());
    if (node.writer().earlier_files() > 0)
      std::fprintf(stderr, " (after %d earlier file(s) of this prefix, kept)",
                   node.writer().earlier_files());
    std::fprintf(stderr, "\n");
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-logger: error: %s\n", e.what());
    return 1;
  }
}

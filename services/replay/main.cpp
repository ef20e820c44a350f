// odonata-replay: a recorded flight (CSV, or a PX4 ULog) onto the bus as VEHICLE_SIGNALS, so
// the live identifier, monitor and logger run on it exactly as next to the vehicle.

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/csv_format_options.hpp"
#include "cli/parse_command_line.hpp"
#include "io/atomic_file.hpp"
#include "io/csv_table.hpp"
#include "records/record_file.hpp"
#include "replay/flight_rows.hpp"
#include "replay_node.hpp"
#include "timeseries/nothing_to_identify.hpp"

int main(int argc, char** argv) {
  std::string path, summary_json;
  odonata::cli::BusCliOptions bus_options;
  bus_options.instance = "replay";
  odonata::replay::FlightRowsOptions rows;
  odonata::replay::ReplayOptions o;
  CLI::App app{
      "Publishes a recorded flight as VEHICLE_SIGNALS (signals_t, one message per row, seq = "
      "row): at its own pace (--speed 1), faster (--speed N), or in lockstep with the "
      "identifiers' and loggers' receipts (--lockstep: as fast as the slowest learns, nothing "
      "lost). Prints what it sent."};
  app.add_option("file", path,
                 "the flight: a CSV (as odonata-fit reads it) or a PX4 ULog (with --signals, "
                 "resampled onto --rate)")
      ->required()
      ->check(CLI::ExistingFile);
  app.add_option("--signals", rows.signals,
                 "columns to send, in order (comma-separated or repeated; default: every column "
                 "but the time and seq columns)")
      ->delimiter(',');
  app.add_option("--time", rows.time_column,
                 "time column in seconds (default: t_s when the file has one)");
  double rate_hz = 0;
  app.add_option("--rate", rate_hz,
                 "samples per second: of a CSV without a time column (default 100), or the grid "
                 "a ULog's signals are resampled onto (default: the slowest one's median, which "
                 "every signal fills)")
      ->capture_default_str()
      ->check(CLI::Range(1e-6, 1e7));
  app.add_option("--from", rows.from_s,
                 "send from this time on (seconds on the file's time axis: a ULog's since its "
                 "start, a CSV's time column, or row / --rate)");
  app.add_option("--to", rows.to_s, "send up to this time (seconds, as --from)");
  bool airborne = false;
  std::string keep_when;
  app.add_flag("--airborne", airborne,
               "send only a PX4 log's airborne part (vehicle_land_detected.landed == 0); other "
               "rows go out as gaps");
  app.add_option("--keep-when", keep_when,
                 "send only the rows where this holds (SIGNAL OP VALUE, OP one of < <= > >= == "
                 "!=); other rows go out as gaps");
  app.add_option("--speed", o.speed, "the flight's time runs this many times faster")
      ->capture_default_str()
      ->check(CLI::Range(1e-3, 1e6));
  app.add_flag("--lockstep", o.lockstep,
               "send each sample once every identifier and logger holds the last one "
               "(VEHICLE_SIGNALS_ACK): the live model then equals odonata-fit's on this file");
  app.add_option("--wait-for", o.wait_for,
                 "lockstep: a consumer instance whose receipt of each sample the next one waits "
                 "for (repeatable)");
  app.add_option("--discover", o.discover_s,
                 "lockstep: seconds to listen for identifier and logger heartbeats first; each "
                 "one heard is waited for too (0: only --wait-for)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--refit-wait", o.refit_wait_s,
                 "lockstep: seconds to wait for consumers landing a scheduled refit (heartbeat "
                 "\"refitting\"), whose timeouts resend nothing and count no resend (default: 600 "
                 "with --key, 45 without, where a forged \"refitting\" looks the same)")
      ->check(CLI::Range(0.0, 86400.0));
  app.add_option("--timeout-ms", o.timeout_ms, "lockstep: resend a sample after this long")
      ->capture_default_str()
      ->check(CLI::Range(1, 600000));
  app.add_option("--max-resends", o.max_resends,
                 "lockstep: resends of one sample before giving up on a consumer")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  app.add_option("--source", o.source,
                 "signals_t.source, the vehicle's name (default: the "
                 "file's name)");
  app.add_option("--summary-json", summary_json, "also write what was sent here");
  odonata::cli::CsvFormatOptions csv_format;
  odonata::cli::AddCsvFormatOptions(&app, &csv_format);
  odonata::cli::AddBusOptions(&app, &bus_options, {"instance name", false});
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  try {
    const auto format = csv_format.Format();
    if (!format) throw std::runtime_error("--decimal ',' needs another --delimiter (';' or tab)");
    if (airborne && !keep_when.empty())
      throw std::runtime_error(
          "--airborne is --keep-when vehicle_land_detected.landed==0: give one");
    if (airborne) rows.keep = odonata::timeseries::Px4Airborne();
    if (!keep_when.empty()) rows.keep = odonata::timeseries::ParseKeepCondition(keep_when);
    // A CSV as it is, or a ULog's chosen signals on one grid with a t_s column.
    odonata::records::RecordOptions ro;
    ro.csv_format = *format;
    ro.signals = rows.signals;
    ro.rate_hz = rate_hz;
    ro.from_s = rows.from_s;
    ro.to_s = rows.to_s;
    ro.keep = rows.keep;
    const odonata::records::Record record = odonata::records::ReadRecord(path, ro);
    for (const auto& n : record.notes) std::fprintf(stderr, "odonata-replay: %s\n", n.c_str());
    for (const auto& w : record.warnings)
      std::fprintf(stderr, "odonata-replay: warning: %s\n", w.c_str());
    if (rows.time_column.empty()) rows.time_column = record.time_column;
    if (rate_hz > 0) rows.rate_hz = rate_hz;
    odonata::replay::FlightRows flight = odonata::replay::FlightRowsFromTable(record.table, rows);
    if (o.source.empty()) o.source = std::filesystem::path(path).stem().string();
    odonata::bus::BusNode bus(bus_options.ToBusOptions("odonata-replay"));
    odonata::replay::ReplayNode node(bus, std::move(flight), o);
    const int code = bus.Run();
    std::printf("odonata-replay: %s\n", node.SummaryLine().c_str());
    if (!summary_json.empty()) {
      odonata::io::WriteFileAtomically(summary_json, node.Summary().dump(1) + "\n");
    }
    return code;
  } catch (const odonata::timeseries::NothingToIdentify& e) {
    std::fprintf(stderr, "odonata-replay: nothing to send: %s\n", e.what());
    return odonata::timeseries::kNothingToIdentifyExit;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-replay: error: %s\n", e.what());
    return 1;
  }
}

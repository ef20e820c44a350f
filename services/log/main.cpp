// odonata-log (also installed as odonata-ulog, its earlier name): what a flight log holds — a PX4
// ULog, an ArduPilot DataFlash log, a Crazyflie micro-SD log, told by content — and its signals as
// the CSV odonata-fit reads.
//   odonata-log topics flight.ulg              every signal: name, type or unit, samples, rate
//   odonata-log export flight.bin --signals ATT.Pitch,RCOU.C3 -o flight.csv

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "io/csv_writer.hpp"
#include "log_topics.hpp"
#include "records/record_file.hpp"
#include "timeseries/nothing_to_identify.hpp"

namespace {

int Export(const std::string& path, const odonata::records::RecordOptions& o,
           const std::string& out_path) {
  if (odonata::records::DetectFormat(path) == odonata::records::RecordFormat::kCsv)
    throw std::runtime_error(
        path +
        " is no flight log this tool reads (not a PX4 ULog, an ArduPilot "
        "DataFlash log, a Crazyflie micro-SD log or a MAVLink .tlog, by its first bytes)");
  const odonata::records::Record r = odonata::records::ReadRecord(path, o);
  for (const auto& w : r.warnings) std::fprintf(stderr, "odonata-log: warning: %s\n", w.c_str());
  for (const auto& n : r.notes) std::fprintf(stderr, "odonata-log: %s\n", n.c_str());
  // What the columns mean goes to stderr, not into the CSV, which every reader takes as it is.
  std::fprintf(stderr,
               "odonata-log: t_s: seconds on the log's own clock; nan: a gap longer than the gap "
               "rule bridges\n");
  odonata::io::CsvWriter out(out_path, r.table.names());
  const auto& names = r.table.names();
  std::vector<const std::vector<double>*> cols;
  for (const auto& n : names) cols.push_back(&r.table.Column(n));
  const std::vector<double>* condition = o.keep ? &r.table.Column(o.keep->signal) : nullptr;
  std::vector<double> row(names.size());
  std::size_t written = 0;
  for (std::size_t i = 0; i < r.table.rows(); ++i) {
    if (condition && !o.keep->Holds((*condition)[i])) continue;
    for (std::size_t c = 0; c < cols.size(); ++c) row[c] = (*cols[c])[i];
    out.WriteRow(row);
    ++written;
  }
  if (written == 0) {
    out.Close();
    std::remove(out_path.c_str());  // no header-only file left behind to be mistaken for data
    throw odonata::timeseries::NothingToIdentify(path + ": the condition " + o.keep->ToString() +
                                                 " holds at no sample: nothing written");
  }
  out.Close();
  std::printf("odonata-log: %zu samples of %zu signals at %.6g Hz written to %s\n", written,
              names.size() - 1, r.rate_hz, out_path.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Reads flight logs — PX4 ULog, ArduPilot DataFlash (.bin), Crazyflie micro-SD, MAVLink "
      ".tlog (told by "
      "their content, not their names): lists their signals, and writes chosen ones as the CSV "
      "odonata-fit reads (odonata-fit and odonata-replay also take such a log as it is)."};
  app.require_subcommand(1);
  std::string path, match, out_path;
  auto* topics = app.add_subcommand("topics", "list every signal: name, type, samples, rate");
  topics->add_option("file", path, "the log")->required()->check(CLI::ExistingFile);
  topics->add_option("--match", match, "only signals whose name contains this");
  odonata::records::RecordOptions o;
  auto* exp = app.add_subcommand("export", "write chosen signals, resampled onto one rate, as CSV");
  exp->add_option("file", path, "the log")->required()->check(CLI::ExistingFile);
  exp->add_option("--signals", o.signals,
                  "signals to write, as `topics` names them (comma-separated or repeated)")
      ->required()
      ->delimiter(',');
  exp->add_option("-o,--output", out_path, "the CSV to write")->required();
  exp->add_option("--rate", o.rate_hz,
                  "the rate in Hz (default: the slowest chosen signal's median rate, which every "
                  "chosen signal fills)")
      ->check(CLI::Range(1e-6, 1e7));
  exp->add_option("--from", o.from_s, "write from this time on (seconds since the log's start)");
  exp->add_option("--to", o.to_s, "write up to this time (seconds since the log's start)");
  bool airborne = false;
  std::string keep_when;
  exp->add_flag("--airborne", airborne,
                "only the airborne part (vehicle_land_detected.landed == 0): rows where it fails "
                "are left out");
  exp->add_option("--keep-when", keep_when,
                  "only the rows where this holds: SIGNAL OP VALUE, OP one of < <= > >= == !=");
  exp->add_option("--max-gap", o.max_gap,
                  "a signal's samples further apart than this many grid periods + 1 leave the "
                  "cells between them empty (nan)")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  try {
    if (*topics) return Topics(path, match);  // log_topics.cpp
    if (airborne && !keep_when.empty())
      throw std::runtime_error(
          "--airborne is --keep-when vehicle_land_detected.landed==0: give one");
    if (airborne) o.keep = odonata::timeseries::Px4Airborne();
    if (!keep_when.empty()) o.keep = odonata::timeseries::ParseKeepCondition(keep_when);
    return Export(path, o, out_path);
  } catch (const odonata::timeseries::NothingToIdentify& e) {
    std::fprintf(stderr, "odonata-log: nothing to write: %s\n", e.what());
    return odonata::timeseries::kNothingToIdentifyExit;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-log: error: %s\n", e.what());
    return 1;
  }
}

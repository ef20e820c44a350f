// odonata-ulog: what a PX4 flight log (ULog) holds, and its signals as the CSV odonata-fit reads.
//   odonata-ulog topics flight.ulg              every signal: name, type, samples, rate
//   odonata-ulog export flight.ulg --signals vehicle_attitude.pitchspeed,... -o flight.csv

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "io/csv_writer.hpp"
#include "records/record_file.hpp"
#include "timeseries/nothing_to_identify.hpp"
#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

namespace {

int Topics(const std::string& path, const std::string& match) {
  const odonata::ulog::UlogFile f = odonata::ulog::Read(path);
  const auto signals = odonata::ulog::ListSignals(f);
  std::size_t data = 0;
  for (const auto& s : f.subscriptions) data += s.timestamps_us.size();
  std::printf(
      "%s: ULog version %d, %zu bytes, %zu topics logged (%zu data messages), %zu "
      "parameters, %zu log messages, %zu dropouts (%llu ms)%s\n",
      path.c_str(), f.version, f.file_size, f.subscriptions.size(), data,
      f.initial_parameters.size(), f.log_messages.size(), f.dropouts.size(),
      static_cast<unsigned long long>(f.dropout_total_ms),
      f.appended_messages ? ", appended data" : "");
  if (!f.complete())
    std::printf("  DAMAGED at byte %llu: %s (what came before is listed)\n",
                static_cast<unsigned long long>(f.problem_offset), f.problem.c_str());
  for (const auto& n : f.notes) std::printf("  note: %s\n", n.c_str());
  std::printf("%-56s %-9s %8s %10s %10s\n", "signal", "type", "samples", "median Hz", "mean Hz");
  std::size_t shown = 0;
  for (const auto& s : signals) {
    if (!match.empty() && s.name.find(match) == std::string::npos) continue;
    std::printf(
        "%-56s %-9s %8zu %10.2f %10.2f%s\n", s.name.c_str(), s.type.c_str(), s.samples,
        s.median_rate_hz, s.mean_rate_hz,
        s.out_of_order ? (" (" + std::to_string(s.out_of_order) + " out of order)").c_str() : "");
    ++shown;
  }
  std::printf("%zu of %zu signals%s\n", shown, signals.size(),
              match.empty() ? "" : (" matching '" + match + "'").c_str());
  return 0;
}

int Export(const std::string& path, const odonata::records::RecordOptions& o,
           const std::string& out_path) {
  if (!odonata::records::IsUlog(path))
    throw std::runtime_error(path + " is not a ULog file (no ULog magic at its start)");
  const odonata::records::Record r = odonata::records::ReadRecord(path, o);
  for (const auto& w : r.warnings) std::fprintf(stderr, "odonata-ulog: warning: %s\n", w.c_str());
  for (const auto& n : r.notes) std::fprintf(stderr, "odonata-ulog: %s\n", n.c_str());
  // What the columns mean goes to stderr, not into the CSV, which every reader takes as it is.
  std::fprintf(stderr,
               "odonata-ulog: t_s: seconds since the log's start; nan: a gap longer than the gap "
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
  std::printf("odonata-ulog: %zu samples of %zu signals at %.6g Hz written to %s\n", written,
              names.size() - 1, r.rate_hz, out_path.c_str());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Reads PX4 flight logs (ULog): lists their signals, and writes chosen ones as the "
      "CSV odonata-fit reads (odonata-fit and odonata-replay also take a .ulg as it is)."};
  app.require_subcommand(1);
  std::string path, match, out_path;
  auto* topics = app.add_subcommand("topics", "list every signal: name, type, samples, rate");
  topics->add_option("file", path, "the .ulg file")->required()->check(CLI::ExistingFile);
  topics->add_option("--match", match, "only signals whose name contains this");
  odonata::records::RecordOptions o;
  auto* exp = app.add_subcommand("export", "write chosen signals, resampled onto one rate, as CSV");
  exp->add_option("file", path, "the .ulg file")->required()->check(CLI::ExistingFile);
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
    if (*topics) return Topics(path, match);
    if (airborne && !keep_when.empty())
      throw std::runtime_error(
          "--airborne is --keep-when vehicle_land_detected.landed==0: give one");
    if (airborne) o.keep = odonata::timeseries::Px4Airborne();
    if (!keep_when.empty()) o.keep = odonata::timeseries::ParseKeepCondition(keep_when);
    return Export(path, o, out_path);
  } catch (const odonata::timeseries::NothingToIdentify& e) {
    std::fprintf(stderr, "odonata-ulog: nothing to write: %s\n", e.what());
    return odonata::timeseries::kNothingToIdentifyExit;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-ulog: error: %s\n", e.what());
    return 1;
  }
}

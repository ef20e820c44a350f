#include "records/record_file.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "timeseries/nothing_to_identify.hpp"
#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

namespace odonata::records {

bool IsUlog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[7] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == 7 && std::string(magic, 4) == "ULog" && magic[4] == 0x01 &&
         magic[5] == 0x12 && magic[6] == 0x35;
}

namespace {

std::string Number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

std::string Hz(double rate) { return Number(rate) + " Hz"; }

// The grid and each signal's own rate, as the user should see them: a log at several rates is
// read at the slowest one's unless told otherwise.
std::string GridNote(const std::string& path, const ulog::ResampledSignals& s) {
  std::string note = path + ": one grid at " + Hz(s.rate_hz) +
                     (s.rate_chosen ? " (the slowest signal's rate; --rate sets another)" : "") +
                     "; logged at:";
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    note += (k ? ", " : " ") + s.names[k] + " " + Hz(s.median_rate_hz[k]);
    if (s.interpolation[k] == timeseries::Interpolation::kHold) note += " (held, a flag)";
  }
  return note;
}

// A given rate far above a signal's own leaves that signal mostly gaps: said with the fix
// instead of a fit on scraps.
void CheckRates(const std::string& path, const ulog::ResampledSignals& s, int max_gap) {
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    if (s.interpolation[k] == timeseries::Interpolation::kHold) continue;
    const double own = s.median_rate_hz[k];
    if (own > 0 && own * (max_gap + 1) < s.rate_hz)
      throw std::invalid_argument(
          path + ": '" + s.names[k] + "' is logged at " + Hz(own) + ", too slow for a " +
          Hz(s.rate_hz) + " grid (its samples would be gaps there): give --rate " + Number(own) +
          " or less, leave --rate out (the slowest signal's rate), or "
          "log it faster");
  }
}

Record ReadUlog(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty())
    throw std::invalid_argument(path +
                                ": a ULog holds hundreds of signals; name the ones to take "
                                "(odonata-ulog topics " +
                                path + " lists them)");
  const ulog::UlogFile file = ulog::Read(path);
  Record r;
  if (!file.complete()) {
    char where[64];
    std::snprintf(where, sizeof where, "%llu",
                  static_cast<unsigned long long>(file.problem_offset));
    r.warnings.push_back(path + ": damaged at byte " + where + " (" + file.problem +
                         "); what was logged before it is used");
  }
  std::vector<std::string> signals = o.signals;
  if (o.keep && std::find(signals.begin(), signals.end(), o.keep->signal) == signals.end())
    signals.push_back(o.keep->signal);
  timeseries::GridOptions grid;
  grid.rate_hz = o.rate_hz;
  grid.max_gap = o.max_gap;
  grid.from_s = o.from_s;
  grid.to_s = o.to_s;
  ulog::ResampledSignals s;
  try {
    s = ulog::Resample(
        file, signals, grid,
        o.keep ? std::vector<std::string>{o.keep->signal} : std::vector<std::string>{});
  } catch (const timeseries::NothingToIdentify& e) {
    throw timeseries::NothingToIdentify(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    if (o.keep && std::string(e.what()).find("'" + o.keep->signal + "'") != std::string::npos)
      throw std::invalid_argument(path + ": the condition " + o.keep->ToString() +
                                  " cannot be read: " + e.what() +
                                  "; name another signal to keep by (--keep-when)");
    throw std::invalid_argument(path + ": " + e.what());
  }
  CheckRates(path, s, o.max_gap);
  r.notes.push_back(GridNote(path, s));
  std::vector<std::string> names{"t_s"};
  std::vector<std::vector<double>> columns{s.t_s};
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    names.push_back(s.names[k]);
    columns.push_back(std::move(s.columns[k]));
    if (s.out_of_order[k] > 0)
      r.warnings.push_back(path + ": " + s.names[k] + ": " + std::to_string(s.out_of_order[k]) +
                           " samples dropped, their time went backwards");
    if (s.gap_cells[k] > 0)
      r.warnings.push_back(path + ": " + s.names[k] + ": " + std::to_string(s.gap_cells[k]) +
                           " of " + std::to_string(s.t_s.size()) +
                           " grid samples fall in gaps longer than the gap rule bridges");
  }
  r.table = io::CsvTable::FromColumns(path, std::move(names), std::move(columns));
  r.time_column = "t_s";
  r.rate_hz = s.rate_hz;
  return r;
}

}  // namespace

Record ReadRecord(const std::string& path, const RecordOptions& options) {
  if (IsUlog(path)) return ReadUlog(path, options);
  Record r{io::CsvTable::Read(path, options.missing, options.csv_format), "", 0, {}, {}};
  return r;
}

}  // namespace odonata::records

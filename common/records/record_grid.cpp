#include "records/record_grid.hpp"

#include <algorithm>
#include <cstdio>
#include <stdexcept>

namespace odonata::records {
namespace {

std::string Number(double x) {
  char text[32];
  std::snprintf(text, sizeof text, "%.4g", x);
  return text;
}

std::string Hz(double rate) { return Number(rate) + " Hz"; }

// The grid and each signal's own rate, as the user should see them: a log at several rates is
// read at the slowest one's unless told otherwise.
std::string GridNote(const std::string& path, const SignalsOnGrid& s) {
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
void CheckRates(const std::string& path, const SignalsOnGrid& s, int max_gap) {
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    if (s.interpolation[k] == timeseries::Interpolation::kHold) continue;
    const double own = s.median_rate_hz[k];
    if (own > 0 && own * (max_gap + 1) < s.rate_hz)
      throw std::invalid_argument(
          path + ": '" + s.names[k] + "' is logged at " + Hz(own) + ", too slow for a " +
          Hz(s.rate_hz) + " grid (its samples would be gaps there): give --rate " + Number(own) +
          " or less, leave --rate out (the slowest signal's rate), or log it faster");
  }
}

}  // namespace

std::vector<std::string> SignalsToRead(const RecordOptions& o) {
  std::vector<std::string> names = o.signals;
  if (o.keep && std::find(names.begin(), names.end(), o.keep->signal) == names.end())
    names.push_back(o.keep->signal);
  return names;
}

SignalsOnGrid ResampleSignals(const std::vector<timeseries::TimedSignal>& signals,
                              const std::vector<std::size_t>& out_of_order,
                              const RecordOptions& o) {
  timeseries::GridOptions grid;
  grid.rate_hz = o.rate_hz;
  grid.max_gap = o.max_gap;
  grid.from_s = o.from_s;
  grid.to_s = o.to_s;
  timeseries::UniformGrid g = timeseries::Resample(signals, grid);
  SignalsOnGrid s;
  s.rate_hz = g.rate_hz;
  s.rate_chosen = g.rate_chosen;
  s.t_s = std::move(g.t_s);
  s.columns = std::move(g.columns);
  s.out_of_order = out_of_order;
  for (std::size_t k = 0; k < signals.size(); ++k) {
    s.names.push_back(signals[k].name);
    s.interpolation.push_back(signals[k].interpolation);
    s.median_rate_hz.push_back(g.signals[k].median_rate_hz);
    s.gap_cells.push_back(g.signals[k].gap_cells);
  }
  return s;
}

Record RecordFromGrid(const std::string& path, SignalsOnGrid s, int max_gap, Record r) {
  CheckRates(path, s, max_gap);
  r.notes.push_back(GridNote(path, s));
  std::vector<std::string> names{"t_s"};
  std::vector<std::vector<double>> columns{s.t_s};
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    names.push_back(s.names[k]);
    columns.push_back(std::move(s.columns[k]));
    if (k < s.out_of_order.size() && s.out_of_order[k] > 0)
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

}  // namespace odonata::records

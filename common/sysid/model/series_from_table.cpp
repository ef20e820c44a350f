#include "sysid/model/series_from_table.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "sysid/model/nothing_to_identify.hpp"
#include "timeseries/gap_rule.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::sysid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool EndsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

// A flag: every finite value 0 or 1, and some of each is not needed (a flag that never changes
// is still a flag).
bool IsFlag(const std::vector<double>& v) {
  bool any = false;
  for (const double x : v) {
    if (!std::isfinite(x)) continue;
    if (x != 0.0 && x != 1.0) return false;
    any = true;
  }
  return any;
}

std::string Seconds(double t) {
  char s[32];
  std::snprintf(s, sizeof s, "%g s", t);
  return s;
}

// The time column in seconds, checked: finite and increasing.
std::vector<double> TimeStamps(const io::CsvTable& table, const SeriesOptions& o) {
  std::vector<double> t = table.Column(o.time_column);
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (!std::isfinite(t[i]))
      throw io::CsvError(table.source() + ": data row " + std::to_string(i + 1) + ": time '" +
                         o.time_column + "' is missing or not finite");
    if (i > 0 && !(t[i] > t[i - 1]))
      throw io::CsvError(table.source() + ": data row " + std::to_string(i + 1) + ": time '" +
                         o.time_column + "' does not increase (" + std::to_string(t[i - 1]) +
                         " then " + std::to_string(t[i]) + ")");
  }
  if (t.size() < 2) throw io::CsvError(table.source() + ": fewer than two time stamps");
  for (double& x : t) x *= o.time_unit_s;
  return t;
}

// The grid: the chosen columns (and the condition's) resampled from a time column.
struct Grid {
  std::vector<double> t_s;
  std::vector<std::vector<double>> columns;  // outputs, inputs, then the condition's
};

Grid FromTimeColumn(const io::CsvTable& table, const SeriesOptions& o,
                    const std::vector<std::string>& names, SeriesReport& r) {
  const std::vector<double> t = TimeStamps(table, o);
  std::vector<timeseries::TimedSignal> signals;
  for (std::size_t k = 0; k < names.size(); ++k) {
    timeseries::TimedSignal s{names[k], t, table.Column(names[k]),
                              timeseries::Interpolation::kLinear};
    const bool is_condition = o.keep && k + 1 == names.size();
    if (is_condition || IsFlag(s.values)) s.interpolation = timeseries::Interpolation::kHold;
    signals.push_back(std::move(s));
  }
  timeseries::GridOptions go;
  go.rate_hz = o.rate_hz;
  go.max_gap = o.max_gap;
  go.max_cells = 100'000'000 * (names.size() + 1);
  timeseries::UniformGrid g;
  try {
    g = timeseries::Resample(signals, go);
  } catch (const std::invalid_argument& e) {
    throw io::CsvError(table.source() + ": " + e.what());
  }
  r.rate_hz = g.rate_hz;
  r.rate_chosen = g.rate_chosen;
  r.slowest = names[g.slowest];
  for (std::size_t k = 0; k < names.size(); ++k) {
    r.columns.push_back(ColumnTiming{names[k], g.signals[k].median_rate_hz,
                                     signals[k].interpolation == timeseries::Interpolation::kHold});
    r.bridged += static_cast<long>(g.signals[k].bridged_cells);
  }
  return Grid{std::move(g.t_s), std::move(g.columns)};
}

Grid FromRows(const io::CsvTable& table, const SeriesOptions& o,
              const std::vector<std::string>& names, SeriesReport& r) {
  Grid g;
  const bool windowed = std::isfinite(o.from_s) || std::isfinite(o.to_s);
  if (windowed && !(o.rate_hz > 0))
    throw io::CsvError(table.source() +
                       ": a window (from, to) is in seconds, and this file has "
                       "no time: name its time column (--time) or give its rate (--rate)");
  for (std::size_t k = 0; k < names.size(); ++k) {
    g.columns.push_back(table.Column(names[k]));
    const bool is_condition = o.keep && k + 1 == names.size();
    if (!is_condition) r.bridged += timeseries::BridgeRuns(&g.columns.back(), o.max_gap);
  }
  r.rate_hz = o.rate_hz > 0 ? o.rate_hz : 0.0;
  g.t_s.resize(table.rows());
  for (std::size_t i = 0; i < g.t_s.size(); ++i)
    g.t_s[i] = r.rate_hz > 0 ? static_cast<double>(i) / r.rate_hz : static_cast<double>(i);
  return g;
}

}  // namespace

double TimeUnitFromName(const std::string& column) {
  for (const char* ms : {"_ms", "[ms]", "(ms)", " ms"})
    if (EndsWith(column, ms)) return 1e-3;
  for (const char* us : {"_us", "[us]", "(us)", " us"})
    if (EndsWith(column, us)) return 1e-6;
  return 1.0;
}

Series SeriesFromTable(const io::CsvTable& table, const SeriesOptions& o, SeriesReport* report) {
  SeriesReport r;
  r.rows = static_cast<long>(table.rows());
  std::vector<std::string> names = o.outputs;
  names.insert(names.end(), o.inputs.begin(), o.inputs.end());
  if (o.keep) names.push_back(o.keep->signal);
  Grid grid =
      o.time_column.empty() ? FromRows(table, o, names, r) : FromTimeColumn(table, o, names, r);
  const long count = static_cast<long>(grid.t_s.size());

  // Rows to learn from: inside the window, the condition holding, every column a value.
  std::vector<char> usable(static_cast<std::size_t>(count), 1);
  // A grid time within a billionth of a period of the window's edge is on it.
  const double eps = 1e-9 / (r.rate_hz > 0 ? r.rate_hz : 1.0);
  for (long k = 0; k < count; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (grid.t_s[i] < o.from_s - eps || grid.t_s[i] > o.to_s + eps) {
      usable[i] = 0;
      ++r.outside_window;
      continue;
    }
    if (o.keep && !o.keep->Holds(grid.columns.back()[i])) {
      usable[i] = 0;
      ++r.cut_by_condition;
      continue;
    }
    for (std::size_t c = 0; c < o.outputs.size() + o.inputs.size(); ++c)
      if (!std::isfinite(grid.columns[c][i])) usable[i] = 0;
  }
  if (r.outside_window == count)
    throw NothingToIdentify(table.source() + ": the window " + Seconds(o.from_s) + " to " +
                            Seconds(o.to_s) + " holds no sample (the data runs from " +
                            Seconds(grid.t_s.front()) + " to " + Seconds(grid.t_s.back()) + ")");
  if (o.keep && r.cut_by_condition + r.outside_window == count)
    throw NothingToIdentify(table.source() + ": the condition " + o.keep->ToString() +
                            " holds at no sample" +
                            (r.outside_window > 0 ? " inside the window" : std::string()) +
                            ": nothing is left to learn from");

  // Segments: maximal runs of usable rows.
  std::vector<std::pair<long, long>> segments;  // [begin, end)
  long begin = -1;
  for (long k = 0; k <= count; ++k) {
    const bool ok = k < count && usable[static_cast<std::size_t>(k)];
    if (ok && begin < 0) begin = k;
    if (!ok && begin >= 0) {
      if (k - begin >= o.min_segment)
        segments.emplace_back(begin, k);
      else
        ++r.dropped_segments;
      begin = -1;
    }
  }
  Series s;
  long total = 0;
  for (const auto& [b, e] : segments) total += e - b;
  s.outputs.resize(total, static_cast<Eigen::Index>(o.outputs.size()));
  s.inputs.resize(total, static_cast<Eigen::Index>(o.inputs.size()));
  long row = 0;
  for (const auto& [b, e] : segments) {
    if (row > 0) s.breaks.push_back(row);
    for (long k = b; k < e; ++k, ++row) {
      for (std::size_t c = 0; c < o.outputs.size(); ++c)
        s.outputs(row, static_cast<Eigen::Index>(c)) = grid.columns[c][static_cast<std::size_t>(k)];
      for (std::size_t c = 0; c < o.inputs.size(); ++c)
        s.inputs(row, static_cast<Eigen::Index>(c)) =
            grid.columns[o.outputs.size() + c][static_cast<std::size_t>(k)];
    }
  }
  r.samples = total;
  r.segments = static_cast<int>(segments.size());
  r.missing = count - total - r.outside_window - r.cut_by_condition;
  if (!segments.empty()) {
    r.first_s = grid.t_s[static_cast<std::size_t>(segments.front().first)];
    r.last_s = grid.t_s[static_cast<std::size_t>(segments.back().second - 1)];
  }
  if (report) *report = r;
  if (total == 0) {
    std::string why = table.source() + ": " + std::to_string(r.rows) +
                      " data rows, but no stretch of " + std::to_string(o.min_segment) +
                      " samples without a gap longer than " + std::to_string(o.max_gap) +
                      " (the lags need " + std::to_string(o.min_segment) + " in a row)";
    // The usual cause in a log at several rates: a column far slower than the grid.
    for (const auto& c : r.columns)
      if (!c.held && c.median_rate_hz > 0 && c.median_rate_hz * (o.max_gap + 1) < r.rate_hz) {
        char fix[200];
        std::snprintf(fix, sizeof fix,
                      "; '%s' is logged at %.3g Hz, too slow for a %.3g Hz grid: "
                      "give --rate %.3g or less, or log it faster",
                      c.name.c_str(), c.median_rate_hz, r.rate_hz, c.median_rate_hz);
        why += fix;
        break;
      }
    throw NothingToIdentify(why);
  }
  return s;
}

}  // namespace odonata::sysid

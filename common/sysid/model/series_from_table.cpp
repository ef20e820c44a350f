#include "sysid/model/series_from_table.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace odonata::sysid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Fills every interior run of at most `max_gap` NaNs by linear interpolation between its
// neighbours; longer runs, and runs at either end, stay NaN. Returns the cells filled.
long BridgeRuns(std::vector<double>* v, int max_gap) {
  long filled = 0;
  const auto n = static_cast<long>(v->size());
  long last_good = -1;
  for (long i = 0; i < n; ++i) {
    if (std::isnan((*v)[static_cast<std::size_t>(i)])) continue;
    const long run = i - last_good - 1;
    if (last_good >= 0 && run > 0 && run <= max_gap) {
      const double a = (*v)[static_cast<std::size_t>(last_good)];
      const double b = (*v)[static_cast<std::size_t>(i)];
      for (long k = last_good + 1; k < i; ++k) {
        const double w = double(k - last_good) / double(i - last_good);
        (*v)[static_cast<std::size_t>(k)] = a + w * (b - a);
      }
      filled += run;
    }
    last_good = i;
  }
  return filled;
}

// The column sampled at t0 + k / rate, k < count: linear interpolation between the surrounding
// finite samples when they are at most (max_gap + 1) periods apart, else NaN. Counts in *bridged
// the points whose surrounding samples are further apart than one and a half periods.
std::vector<double> Resample(const std::vector<double>& t, const std::vector<double>& v, double t0,
                             double rate, long count, int max_gap, long* bridged) {
  std::vector<double> ts, vs;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (std::isfinite(v[i])) {
      ts.push_back(t[i]);
      vs.push_back(v[i]);
    }
  std::vector<double> out(static_cast<std::size_t>(count), kNaN);
  const double period = 1.0 / rate, reach = (max_gap + 1) * period * (1 + 1e-9);
  // Time stamps within a billionth of a period of a grid point count as on it (t0 + k / rate
  // rounds differently from the logged stamps).
  const double eps = 1e-9 * period;
  std::size_t j = 0;
  for (long k = 0; k < count; ++k) {
    const double tk = t0 + double(k) * period;
    while (j + 1 < ts.size() && ts[j + 1] <= tk + eps) ++j;
    if (ts.empty() || ts[j] > tk + eps) continue;
    if (std::abs(ts[j] - tk) <= eps) {
      out[static_cast<std::size_t>(k)] = vs[j];
      continue;
    }
    if (j + 1 >= ts.size()) continue;  // after the last sample
    const double span = ts[j + 1] - ts[j];
    if (span > reach) continue;
    const double w = (tk - ts[j]) / span;
    out[static_cast<std::size_t>(k)] = vs[j] + w * (vs[j + 1] - vs[j]);
    if (span > 1.5 * period) ++*bridged;
  }
  return out;
}

}  // namespace

Series SeriesFromTable(const io::CsvTable& table, const SeriesOptions& o, SeriesReport* report) {
  SeriesReport r;
  r.rows = static_cast<long>(table.rows());
  std::vector<std::string> names = o.outputs;
  names.insert(names.end(), o.inputs.begin(), o.inputs.end());
  std::vector<std::vector<double>> grid;
  long count = r.rows;
  if (o.time_column.empty()) {
    for (const auto& n : names) grid.push_back(table.Column(n));
    for (auto& c : grid) r.bridged += BridgeRuns(&c, o.max_gap);
  } else {
    const auto& t = table.Column(o.time_column);
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
    double rate = o.rate_hz;
    if (!(rate > 0)) {
      std::vector<double> dt;
      for (std::size_t i = 1; i < t.size(); ++i) dt.push_back(t[i] - t[i - 1]);
      std::nth_element(dt.begin(), dt.begin() + static_cast<long>(dt.size() / 2), dt.end());
      rate = 1.0 / dt[dt.size() / 2];
    }
    r.rate_hz = rate;
    count = static_cast<long>(std::floor((t.back() - t.front()) * rate + 1e-9)) + 1;
    if (count > 100'000'000)
      throw io::CsvError(table.source() + ": resampling at " + std::to_string(rate) +
                         " Hz would make " + std::to_string(count) + " samples");
    for (const auto& n : names)
      grid.push_back(Resample(t, table.Column(n), t.front(), rate, count, o.max_gap, &r.bridged));
  }

  // Segments: maximal runs of rows where every column has a value.
  std::vector<std::pair<long, long>> segments;  // [begin, end)
  long begin = -1;
  for (long k = 0; k <= count; ++k) {
    bool complete = k < count;
    for (std::size_t c = 0; complete && c < grid.size(); ++c)
      complete = std::isfinite(grid[c][static_cast<std::size_t>(k)]);
    if (complete && begin < 0) begin = k;
    if (!complete && begin >= 0) {
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
        s.outputs(row, static_cast<Eigen::Index>(c)) = grid[c][static_cast<std::size_t>(k)];
      for (std::size_t c = 0; c < o.inputs.size(); ++c)
        s.inputs(row, static_cast<Eigen::Index>(c)) =
            grid[o.outputs.size() + c][static_cast<std::size_t>(k)];
    }
  }
  r.samples = total;
  r.segments = static_cast<int>(segments.size());
  r.missing = count - total;
  if (report) *report = r;
  if (total == 0)
    throw io::CsvError(table.source() + ": " + std::to_string(r.rows) +
                       " data rows, but no stretch of " + std::to_string(o.min_segment) +
                       " samples without a gap longer than " + std::to_string(o.max_gap) +
                       " (the lags need " + std::to_string(o.min_segment) + " in a row)");
  return s;
}

}  // namespace odonata::sysid

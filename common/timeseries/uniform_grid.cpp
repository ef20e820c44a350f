#include "timeseries/uniform_grid.hpp"

#include "timeseries/nothing_to_identify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace odonata::timeseries {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string Seconds(double t) {
  char s[32];
  std::snprintf(s, sizeof s, "%.3f s", t);
  return s;
}

// A signal's finite samples only: a missing cell of a CSV is no sample.
struct Samples {
  std::vector<double> t, v;
};

Samples FiniteSamples(const TimedSignal& s) {
  if (s.t_s.size() != s.values.size())
    throw std::invalid_argument("signal '" + s.name + "': " + std::to_string(s.t_s.size()) +
                                " times but " + std::to_string(s.values.size()) + " values");
  Samples out;
  for (std::size_t i = 0; i < s.t_s.size(); ++i)
    if (std::isfinite(s.values[i]) && std::isfinite(s.t_s[i])) {
      out.t.push_back(s.t_s[i]);
      out.v.push_back(s.values[i]);
    }
  return out;
}

// One interpolated column: the straight line between the two samples around each grid time,
// NaN where they are further apart than `reach` seconds or the time is outside them.
std::vector<double> Interpolated(const Samples& s, const std::vector<double>& grid, double period,
                                 double reach, SignalOnGrid* info) {
  std::vector<double> out(grid.size(), kNaN);
  const double eps = 1e-9 * period;  // a logged time this close to a grid time is on it
  std::size_t j = 0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    const double tk = grid[k];
    while (j + 1 < s.t.size() && s.t[j + 1] <= tk + eps) ++j;
    if (s.t[j] > tk + eps) continue;  // before the first sample (outside the span)
    if (std::abs(s.t[j] - tk) <= eps) {
      out[k] = s.v[j];
      continue;
    }
    if (j + 1 >= s.t.size()) continue;  // after the last sample
    const double span = s.t[j + 1] - s.t[j];
    if (span > reach) {
      ++info->gap_cells;
      continue;
    }
    out[k] = s.v[j] + (s.v[j + 1] - s.v[j]) * ((tk - s.t[j]) / span);
    if (span > 1.5 * period) ++info->bridged_cells;
  }
  return out;
}

// One held column: the last sample at or before each grid time.
std::vector<double> Held(const Samples& s, const std::vector<double>& grid, double period) {
  std::vector<double> out(grid.size(), kNaN);
  const double eps = 1e-9 * period;
  std::size_t j = 0;
  for (std::size_t k = 0; k < grid.size(); ++k) {
    while (j + 1 < s.t.size() && s.t[j + 1] <= grid[k] + eps) ++j;
    if (s.t[j] <= grid[k] + eps) out[k] = s.v[j];
  }
  return out;
}

}  // namespace

double MedianRateHz(const std::vector<double>& t_s) {
  std::vector<double> dt;
  dt.reserve(t_s.size());
  for (std::size_t i = 1; i < t_s.size(); ++i)
    if (t_s[i] > t_s[i - 1]) dt.push_back(t_s[i] - t_s[i - 1]);
  if (dt.empty()) return 0.0;
  const auto mid = dt.begin() + static_cast<std::ptrdiff_t>(dt.size() / 2);
  std::nth_element(dt.begin(), mid, dt.end());
  double median = *mid;
  if (dt.size() % 2 == 0) median = 0.5 * (median + *std::max_element(dt.begin(), mid));
  return 1.0 / median;
}

UniformGrid Resample(const std::vector<TimedSignal>& signals, const GridOptions& o) {
  if (signals.empty()) throw std::invalid_argument("resampling needs at least one signal");
  if (!std::isfinite(o.rate_hz) || o.rate_hz < 0.0)
    throw std::invalid_argument(
        "the grid's rate must be a finite number of Hz >= 0 (0: the "
        "slowest signal's), not " +
        std::to_string(o.rate_hz));
  if (o.max_gap < 0)
    throw std::invalid_argument("max_gap must be >= 0, not " + std::to_string(o.max_gap));
  if (!(o.from_s < o.to_s))
    throw std::invalid_argument("the window's start (" + Seconds(o.from_s) +
                                ") must come before its end (" + Seconds(o.to_s) + ")");

  UniformGrid g;
  std::vector<Samples> samples;
  samples.reserve(signals.size());
  const bool any_linear = std::any_of(signals.begin(), signals.end(), [](const TimedSignal& s) {
    return s.interpolation == Interpolation::kLinear;
  });
  double begin = -std::numeric_limits<double>::infinity();
  double end = std::numeric_limits<double>::infinity();
  double slowest_hz = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < signals.size(); ++i) {
    samples.push_back(FiniteSamples(signals[i]));
    const Samples& s = samples.back();
    if (s.t.empty()) throw std::invalid_argument("signal '" + signals[i].name + "' has no samples");
    SignalOnGrid info;
    info.samples = s.t.size();
    info.median_rate_hz = MedianRateHz(s.t);
    g.signals.push_back(info);
    const bool linear = signals[i].interpolation == Interpolation::kLinear;
    if (linear || !any_linear) {
      begin = std::max(begin, s.t.front());
      end = std::min(end, s.t.back());
    }
    if (linear && info.median_rate_hz > 0.0 && info.median_rate_hz < slowest_hz) {
      slowest_hz = info.median_rate_hz;
      g.slowest = i;
    }
  }
  if (end < begin)
    throw std::invalid_argument("the signals' time spans do not overlap (the latest starts at " +
                                Seconds(begin) + ", the earliest ends at " + Seconds(end) + ")");
  if (o.from_s > end || o.to_s < begin)
    throw NothingToIdentify("the window " + Seconds(o.from_s) + " to " + Seconds(o.to_s) +
                            " is outside the signals' common span, " + Seconds(begin) + " to " +
                            Seconds(end));
  begin = std::max(begin, o.from_s);
  end = std::min(end, o.to_s);
  g.rate_chosen = !(o.rate_hz > 0.0);
  g.rate_hz = g.rate_chosen ? slowest_hz : o.rate_hz;
  if (!std::isfinite(g.rate_hz))
    throw std::invalid_argument(
        "no rate to resample at: no interpolated signal has two distinct "
        "times; give the rate");
  const double period = 1.0 / g.rate_hz;
  const double span_periods = (end - begin) * g.rate_hz;
  const double max_points =
      static_cast<double>(o.max_cells) / static_cast<double>(signals.size() + 1);
  if (!(span_periods + 1.0 <= max_points))
    throw std::invalid_argument("resampling " + std::to_string(signals.size()) + " signals over " +
                                std::to_string(end - begin) + " s at " + std::to_string(g.rate_hz) +
                                " Hz makes more than " + std::to_string(o.max_cells) +
                                " cells; give a lower rate or a window (from, to)");
  const auto points = static_cast<std::size_t>(std::floor(span_periods + 1e-9)) + 1;
  g.t_s.resize(points);
  // Each time from its index, so that no rounding accumulates along a long grid.
  for (std::size_t i = 0; i < points; ++i) g.t_s[i] = begin + static_cast<double>(i) / g.rate_hz;
  // A relative tolerance lets neighbours exactly max_gap + 1 periods apart through despite the
  // rounding of the period.
  const double reach = (o.max_gap + 1.0) * period * (1.0 + 1e-9);
  for (std::size_t i = 0; i < signals.size(); ++i)
    g.columns.push_back(signals[i].interpolation == Interpolation::kHold
                            ? Held(samples[i], g.t_s, period)
                            : Interpolated(samples[i], g.t_s, period, reach, &g.signals[i]));
  return g;
}

}  // namespace odonata::timeseries

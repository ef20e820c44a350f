#pragma once
// Signals sampled at their own times, put on one uniform time grid: the one resampler behind every
// log odonata reads (a CSV with a time column, a PX4 ULog), so that a log at several rates reads
// the same wherever it is taken.
//
// The rules (docs/guide/real-flights.md, "One grid"):
//  - Rate: the one given, or else the slowest interpolated signal's median rate: the fastest grid
//    every chosen signal fills. On a faster grid a slow signal's samples lie several periods
//    apart, which the gap rule reads as gaps.
//  - Interpolated signals (measurements, commands) take the straight line between their own two
//    samples around a grid time (a sample within a billionth of a period of it is taken as is).
//    Where those two samples are more than (max_gap + 1) grid periods apart the cell is NaN: a
//    gap, which the reader bridges or splits at under its own rules.
//  - Held signals (flags, enumerations: a state that holds until it changes, and that PX4 logs
//    when it changes) take their last sample at or before the grid time, with no gap limit; NaN
//    before their first sample. A flag is 0 or 1, never 0.8125.
//  - Span: from the latest first sample to the earliest last one of the interpolated signals (of
//    all signals when none is interpolated), cut to [from_s, to_s].

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace odonata::timeseries {

enum class Interpolation {
  kLinear,  ///< a quantity that moves continuously between samples
  kHold,    ///< a state that holds until its next sample (a flag, an enumeration)
};

struct TimedSignal {
  std::string name;
  std::vector<double> t_s;     ///< seconds, non-decreasing
  std::vector<double> values;  ///< one per time; a non-finite value is no sample
  Interpolation interpolation = Interpolation::kLinear;
};

struct GridOptions {
  double rate_hz = 0.0;  ///< the grid's rate; 0: the slowest interpolated signal's median rate
  int max_gap = 3;       ///< see the gap rule above
  double from_s = -std::numeric_limits<double>::infinity();  ///< window, seconds
  double to_s = std::numeric_limits<double>::infinity();
  std::size_t max_cells = 50'000'000;  ///< grid points × (signals + 1) refused beyond (400 MB)
};

/// What the grid made of one signal.
struct SignalOnGrid {
  std::size_t samples = 0;      ///< finite samples it has
  double median_rate_hz = 0.0;  ///< 1 / its median interval between distinct times (0: fewer)
  std::size_t gap_cells = 0;    ///< grid cells left NaN by its gaps (interpolated signals)
  /// Cells interpolated between samples more than one and a half grid periods apart: bridged.
  std::size_t bridged_cells = 0;
};

struct UniformGrid {
  double rate_hz = 0.0;
  bool rate_chosen = false;  ///< the rate was not given: the slowest signal's
  std::size_t slowest = 0;   ///< the interpolated signal with the lowest median rate
  std::vector<double> t_s;   ///< t_s[i] = t_s[0] + i / rate_hz
  std::vector<std::vector<double>> columns;  ///< one per signal, in the order given
  std::vector<SignalOnGrid> signals;
};

/// 1 / the median interval between consecutive distinct times (0 with fewer than two): the rate
/// a signal was logged at, unmoved by a few long gaps or bursts.
double MedianRateHz(const std::vector<double>& t_s);

/// @throws std::invalid_argument (saying what to do) for no signals, a signal without samples,
///   a negative or non-finite rate, a negative max_gap, no rate to be had, spans that do not
///   overlap, a window outside the span, or a grid beyond max_cells.
UniformGrid Resample(const std::vector<TimedSignal>& signals, const GridOptions& options);

}  // namespace odonata::timeseries

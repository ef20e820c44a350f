#pragma once
// The numeric signals of a ULog file, by name, and their resampling onto one uniform time grid,
// which is what identification reads (the caller turns it into a table: t_s and the signals).
//
// Names: "topic.field", an array element "topic.field[i]", a nested format's field
// "topic.inner.field" (in an array of them "topic.inner[i].field"), and the second and later
// instances of a topic logged several times "topic/1.field" (instance 0 is plain "topic.field").
// The "timestamp" field of each topic is the time axis, not a signal; char fields are text, not
// signals. Derived signals: a topic with an attitude quaternion "q" (float[4], PX4's [w, x, y, z]
// rotating body to NED) also offers its Euler angles (Z-Y-X) as "topic.roll_rad", "topic.pitch_rad"
// and "topic.yaw_rad"; roll and yaw are unwrapped (continuous through ±π), so that resampling
// never interpolates across a wrap.
//
// Kinds: bool and 8-bit integer fields are states (flags, enumerations: vehicle_land_detected's
// "landed", vehicle_status's "nav_state") and are held on a grid, never interpolated; every other
// field is interpolated (timeseries/uniform_grid.hpp).
//
// Time: seconds since the header's start time. A sample whose timestamp is earlier than the one
// before it in the same topic instance (PX4 logs the time each message was published, so this only
// follows a clock reset or corruption) is dropped and counted in `out_of_order`: times are then
// non-decreasing. Samples with equal timestamps are kept, in file order.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "timeseries/uniform_grid.hpp"
#include "ulog/ulog_file.hpp"

namespace odonata::ulog {

struct SignalInfo {
  std::string name;
  std::string topic;
  std::uint8_t multi_id = 0;
  std::string type;  ///< the field's C type: "float", "uint16_t", "bool", …
  timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
  std::size_t samples = 0;       ///< kept samples
  std::size_t out_of_order = 0;  ///< dropped: their time went backwards, or leapt ahead alone
  /// 1 / the median interval between consecutive samples of distinct times (0 with fewer than
  /// two): the rate the topic was published at, unmoved by a few long gaps.
  double median_rate_hz = 0.0;
  /// (samples - 1) / time span (0 with fewer than two): the average, which gaps and bursts move.
  double mean_rate_hz = 0.0;
};

/// Every numeric signal of the topics that have samples, in the order of their subscriptions and
/// fields.
std::vector<SignalInfo> ListSignals(const UlogFile& file);

struct SignalSamples {
  std::string name;
  timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
  std::vector<double> t_s;     ///< seconds since the file's start, non-decreasing
  std::vector<double> values;  ///< as double (64-bit integers above 2^53 rounded)
  std::size_t out_of_order = 0;
};

/// The samples of signal `name`.
/// @throws std::invalid_argument for a name that is no signal of the file, naming the nearest
///   ones (or saying that its topic logged no sample: such topics have no signals).
SignalSamples Extract(const UlogFile& file, const std::string& name);

struct ResampledSignals {
  double rate_hz = 0.0;
  bool rate_chosen = false;  ///< no rate given: the slowest interpolated signal's
  std::vector<double> t_s;   ///< t_s[i] = t_s[0] + i / rate_hz, seconds since the file's start
  std::vector<std::string> names;
  /// columns[k][i]: signal names[k] at t_s[i]; NaN where its samples are too far apart.
  std::vector<std::vector<double>> columns;
  std::vector<std::size_t> out_of_order;  ///< per signal, dropped before resampling
  std::vector<std::size_t> gap_cells;     ///< per signal, the NaN cells its gaps made
  std::vector<double> median_rate_hz;     ///< per signal, the rate it was logged at
  std::vector<timeseries::Interpolation> interpolation;  ///< per signal
};

/// Grid points × (signals + 1) beyond which Resample refuses (400 MB of doubles).
inline constexpr std::size_t kMaxResampledCells = 50'000'000;

/// Resamples `names` onto one uniform grid under the rules of timeseries/uniform_grid.hpp: at
/// `grid.rate_hz` (0: the slowest interpolated signal's median rate, which every signal fills),
/// over the span they all cover cut to the window [grid.from_s, grid.to_s] (seconds since the
/// file's start), interpolated signals NaN where their own samples are more than max_gap + 1 grid
/// periods apart, held ones (flags) carried to the next sample.
/// @throws std::invalid_argument for no or repeated names, an unknown name, a signal without
///   samples, a bad rate or max_gap, no rate to be had, spans that do not overlap, a window
///   outside them, or a grid larger than kMaxResampledCells.
/// Names in `held` are held whatever their type (the signal a keep condition reads: a threshold
/// on thrust is a state of the flight, and does not choose the grid).
ResampledSignals Resample(const UlogFile& file, const std::vector<std::string>& names,
                          const timeseries::GridOptions& grid,
                          const std::vector<std::string>& held = {});

/// Resample at `rate_hz` (0: chosen) with `max_gap`, over the whole common span.
ResampledSignals Resample(const UlogFile& file, const std::vector<std::string>& names,
                          double rate_hz, int max_gap);

}  // namespace odonata::ulog

#pragma once
// A recorded table (CSV) → the Series a model learns from, under the documented rules for real
// logs (docs/identifier.md §7.1): an optional time column resampled onto one grid every chosen
// column fills (timeseries/uniform_grid.hpp), short gaps and missing cells bridged by linear
// interpolation, longer ones splitting the data into segments, and an optional window or keep
// condition cutting out what is not to be learned. Never a crash: every problem is an error naming
// the file, line or column.

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "timeseries/keep_condition.hpp"

namespace odonata::sysid {

struct SeriesOptions {
  std::vector<std::string> outputs, inputs;  ///< the columns, in the model's order
  /// Time stamps, increasing, in units of time_unit_s seconds; empty: one row per sample,
  /// uniformly spaced (rate_hz apart when it is given).
  std::string time_column;
  double time_unit_s = 1.0;  ///< seconds per unit of the time column (1e-3: milliseconds)
  /// With a time column: the rate to resample to (0: the slowest chosen column's median rate).
  /// Without one: the rows' rate, when known (0: unknown; time is then counted in samples).
  double rate_hz = 0;
  /// The longest run of missing samples bridged by linear interpolation (per column, in samples
  /// of the output rate); a longer one splits the data into segments.
  int max_gap = 3;
  /// Segments shorter than this many samples are dropped (the lags need some).
  int min_segment = 2;
  /// Window in seconds on the table's own time axis (the time column; row / rate_hz without
  /// one): rows outside are not read.
  double from_s = -std::numeric_limits<double>::infinity();
  double to_s = std::numeric_limits<double>::infinity();
  /// Rows where this condition on a column fails are cut out as gaps are (the column is held,
  /// never interpolated).
  std::optional<timeseries::KeepCondition> keep;
};

struct ColumnTiming {
  std::string name;
  double median_rate_hz = 0;  ///< its own rate, from its finite samples (with a time column)
  bool held = false;          ///< a flag (0/1 only): held on the grid, never interpolated
};

struct SeriesReport {
  long rows = 0;             ///< rows in the table
  long samples = 0;          ///< samples in the series (all segments)
  long bridged = 0;          ///< cells filled by interpolation
  long missing = 0;          ///< samples dropped in gaps too long to bridge (or at the ends)
  int segments = 0;          ///< segments kept
  int dropped_segments = 0;  ///< segments too short to use
  double rate_hz = 0;        ///< the rate the series has (0: unknown, time counted in samples)
  bool rate_chosen = false;  ///< the rate was the slowest column's, not given
  std::string slowest;       ///< that column
  std::vector<ColumnTiming> columns;  ///< with a time column, each chosen column's timing
  long outside_window = 0;            ///< grid samples outside [from_s, to_s]
  long cut_by_condition = 0;          ///< grid samples where the keep condition failed
  double first_s = 0, last_s = 0;     ///< the time of the first and last sample kept
};

/// The time unit a column's name declares ("_ms", "[ms]", "(ms)", "_us", "[us]", "(us)"; else
/// seconds): seconds per unit.
double TimeUnitFromName(const std::string& column);

/// @throws io::CsvError naming the source and the problem (a missing column, a time stamp that
///   does not increase or is not finite, a window with no rate, nothing left to learn from).
Series SeriesFromTable(const io::CsvTable& table, const SeriesOptions& options,
                       SeriesReport* report = nullptr);

}  // namespace odonata::sysid

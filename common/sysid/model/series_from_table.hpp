#pragma once
// A recorded table (CSV) → the Series a model learns from, under the documented rules for real
// logs (docs/identifier.md §7.1): an optional time column resampled onto a fixed rate, short gaps
// and missing cells bridged by linear interpolation, longer ones splitting the data into
// segments. Never a crash: every problem is an error naming the file, line or column.

#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

struct SeriesOptions {
  std::vector<std::string> outputs, inputs;  ///< the columns, in the model's order
  /// Time stamps in seconds, increasing; empty: one row per sample, uniformly spaced.
  std::string time_column;
  /// With a time column: the rate to resample to (0: the median rate of the time stamps).
  double rate_hz = 0;
  /// The longest run of missing samples bridged by linear interpolation (per column, in samples
  /// of the output rate); a longer one splits the data into segments.
  int max_gap = 3;
  /// Segments shorter than this many samples are dropped (the lags need some).
  int min_segment = 2;
};

struct SeriesReport {
  long rows = 0;             ///< rows in the table
  long samples = 0;          ///< samples in the series (all segments)
  long bridged = 0;          ///< cells filled by interpolation
  long missing = 0;          ///< samples dropped in gaps too long to bridge (or at the ends)
  int segments = 0;          ///< segments kept
  int dropped_segments = 0;  ///< segments too short to use
  double rate_hz = 0;        ///< the rate the series has (with a time column)
};

/// @throws io::CsvError naming the source and the problem (a missing column, a time stamp that
///   does not increase or is not finite, nothing left to learn from).
Series SeriesFromTable(const io::CsvTable& table, const SeriesOptions& options,
                       SeriesReport* report = nullptr);

}  // namespace odonata::sysid

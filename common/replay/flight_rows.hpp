#pragma once
// A recorded flight as the samples a replay publishes: the chosen signals row by row, each row
// with its time, so odonata-replay can send it at the flight's own pace, faster, or in lockstep.
// Knows nothing of the bus.

#include <cstdint>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "timeseries/keep_condition.hpp"

namespace odonata::replay {

struct FlightRowsOptions {
  /// The columns to send, in this order; empty: every column but the time column.
  std::vector<std::string> signals;
  /// Time stamps in seconds (increasing); empty: "t_s" when the table has it, else rows are
  /// `rate_hz` apart.
  std::string time_column;
  double rate_hz = 100.0;  ///< without a time column: samples per second
  /// Only the rows inside this window are sent (seconds on the file's time axis: the time
  /// column, or row / rate_hz); the first one sent is seq 0.
  double from_s = -std::numeric_limits<double>::infinity();
  double to_s = std::numeric_limits<double>::infinity();
  /// Rows where this fails are not sent (the receivers see a gap); its column is not sent.
  std::optional<timeseries::KeepCondition> keep;
};

struct FlightRows {
  std::string source;                     ///< the file
  std::vector<std::string> names;         ///< the signals sent, in order
  std::vector<double> times_s;            ///< per row, from 0, increasing
  std::vector<std::vector<double>> rows;  ///< per row, one value per name (NaN: missing)
  /// Row k goes out as sample seq k; a row holding a NaN (a gap the file has) is not sent, so
  /// the receivers see a gap there, as when a sample is lost.
  bool Complete(std::size_t row) const;
};

/// @throws io::CsvError naming the column that is missing (with the ones there are), a time
///   column that does not increase, or a table with no row.
FlightRows FlightRowsFromTable(const io::CsvTable& table, const FlightRowsOptions& options);

}  // namespace odonata::replay

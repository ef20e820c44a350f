#pragma once
// A log's chosen signals on one grid, whatever format they came from, and what every reader says
// of it: the grid and each signal's own rate, a given rate too fast for a signal, the gaps and
// dropped samples. One home, so that a ULog, a DataFlash log and a Crazyflie log read alike.

#include <cstddef>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "records/record_file.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::records {

struct SignalsOnGrid {
  double rate_hz = 0.0;
  bool rate_chosen = false;
  std::vector<double> t_s;
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  std::vector<double> median_rate_hz;
  std::vector<timeseries::Interpolation> interpolation;
  std::vector<std::size_t> gap_cells;
  std::vector<std::size_t> out_of_order;  ///< per signal, dropped by the reader before the grid
};

/// The signals resampled by the shared rules (timeseries::Resample); `out_of_order` per signal.
/// @throws timeseries::NothingToIdentify for a window outside the signals, std::invalid_argument
///   for the rest (as timeseries::Resample).
SignalsOnGrid ResampleSignals(const std::vector<timeseries::TimedSignal>& signals,
                              const std::vector<std::size_t>& out_of_order,
                              const RecordOptions& options);

/// The names to read: the chosen signals, and the keep condition's when it is not one of them.
std::vector<std::string> SignalsToRead(const RecordOptions& options);

/// The record: a table (t_s, then the signals), the grid said in a note, and a warning for each
/// signal's gaps and dropped samples.
/// @throws std::invalid_argument when a given rate is far above a signal's own (the signal and
///   the fix named).
Record RecordFromGrid(const std::string& path, SignalsOnGrid grid, int max_gap, Record record);

}  // namespace odonata::records

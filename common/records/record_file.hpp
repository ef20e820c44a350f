#pragma once
// A recorded flight's file as one table, whatever wrote it: a CSV as it is, or an autopilot's log
// (PX4 ULog, ArduPilot DataFlash, Crazyflie micro-SD) with its chosen signals resampled onto one
// time grid (column t_s, seconds on the log's own clock). Every program that reads a record
// (odonata-fit, odonata-replay, odonata-log export) reads it here, so a log is taken wherever a
// CSV is, under the same gap rules (records/record_grid.hpp).

#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "timeseries/keep_condition.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::records {

/// True when `path` starts with the ULog magic ("ULog" 01 12 35), whatever its name.
bool IsUlog(const std::string& path);

/// What a record file is, told by its content, never by its name alone: a PX4 ULog, an
/// ArduPilot DataFlash log (0xA3 0x95 and an FMT record first), a Crazyflie micro-SD deck log
/// (0xBC, version 1 or 2), a MAVLink telemetry log (a ground station's .tlog: a big-endian
/// timestamp, then a frame), else a CSV.
enum class RecordFormat { kCsv, kUlog, kDataflash, kCrazyflieUsd, kMavlinkTlog };
RecordFormat DetectFormat(const std::string& path);
/// "CSV", "PX4 ULog", "ArduPilot DataFlash", "Crazyflie micro-SD", "MAVLink telemetry log".
const char* FormatName(RecordFormat format);

struct RecordOptions {
  io::MissingCells missing = io::MissingCells::kKeepAsNaN;
  io::CsvFormat csv_format;  ///< CSV only
  /// Logs only: the signals to take, by name as the log's ecosystem names them (a ULog's
  /// topic.field[i], a DataFlash log's ATT.Pitch or IMU[1].GyrX, a Crazyflie log's gyro.x).
  std::vector<std::string> signals;
  /// Logs only: the grid's rate (0: the slowest chosen signal's median rate, which every chosen
  /// signal fills; timeseries/uniform_grid.hpp).
  double rate_hz = 0;
  /// Logs only: where a signal's own samples are more than max_gap + 1 grid periods apart its
  /// cells are missing (NaN), for the reader's gap rules to bridge or split.
  int max_gap = 3;
  /// Logs only: the grid covers only this window (seconds since the log's start).
  double from_s = -std::numeric_limits<double>::infinity();
  double to_s = std::numeric_limits<double>::infinity();
  /// Logs only: this condition's signal is read too (held, as a column of the table), for the
  /// series reader to keep only the samples where it holds.
  std::optional<timeseries::KeepCondition> keep;
};

struct Record {
  io::CsvTable table;
  std::string time_column;  ///< "t_s" for a ULog; "" for a CSV (the caller's choice holds)
  double rate_hz = 0;       ///< a ULog's grid rate
  /// What the reader should hear of: a damaged ULog read up to its damage, samples dropped for
  /// time going backwards, cells left missing by gaps.
  std::vector<std::string> warnings;
  /// What the reader should know: the grid a ULog was put on, and each signal's own rate.
  std::vector<std::string> notes;
};

/// @throws io::CsvError (a CSV's problem, with file, line and column) or std::runtime_error /
///   std::invalid_argument (a ULog that is not one, no --signals for it, an unknown signal with
///   the nearest names, a given rate far above a signal's own) naming the file.
Record ReadRecord(const std::string& path, const RecordOptions& options);

}  // namespace odonata::records

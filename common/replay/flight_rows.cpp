#include "replay/flight_rows.hpp"

#include <cmath>
#include <string>

namespace odonata::replay {

bool FlightRows::Complete(std::size_t row) const {
  for (const double v : rows.at(row))
    if (!std::isfinite(v)) return false;
  return true;
}

FlightRows FlightRowsFromTable(const io::CsvTable& table, const FlightRowsOptions& options) {
  FlightRows f;
  f.source = table.source();
  if (table.rows() == 0) throw io::CsvError(table.source() + ": no sample to replay");
  std::string time = options.time_column;
  if (time.empty() && table.HasColumn("t_s")) time = "t_s";
  f.names = options.signals;
  if (f.names.empty()) {
    // odonata-logger export's own bookkeeping column is not a signal of the vehicle.
    for (const auto& n : table.names())
      if (n != time && n != "seq") f.names.push_back(n);
    if (f.names.empty()) throw io::CsvError(table.source() + ": no column to replay but time");
  }
  std::vector<const std::vector<double>*> columns;
  for (const auto& n : f.names) columns.push_back(&table.Column(n));  // names what is missing
  const std::size_t rows = table.rows();
  f.times_s.resize(rows);
  if (!time.empty()) {
    const auto& t = table.Column(time);
    for (std::size_t r = 0; r < rows; ++r) {
      if (!std::isfinite(t[r]) || (r > 0 && !(t[r] > t[r - 1])))
        throw io::CsvError(table.source() + ": column '" + time + "' row " + std::to_string(r + 1) +
                           ": the time stamps must be finite and increase (" +
                           std::to_string(t[r]) + ")");
      f.times_s[r] = t[r] - t[0];
    }
  } else {
    if (!(options.rate_hz > 0) || !std::isfinite(options.rate_hz))
      throw io::CsvError(table.source() + ": no time column, and the rate is not positive");
    for (std::size_t r = 0; r < rows; ++r) f.times_s[r] = static_cast<double>(r) / options.rate_hz;
  }
  f.rows.assign(rows, std::vector<double>(f.names.size()));
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < columns.size(); ++c) f.rows[r][c] = (*columns[c])[r];
  return f;
}

}  // namespace odonata::replay

#include "replay/flight_rows.hpp"

#include "timeseries/nothing_to_identify.hpp"

#include <algorithm>
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
  for (std::size_t i = 0; i < f.names.size(); ++i)
    for (std::size_t j = 0; j < i; ++j)
      if (f.names[i] == f.names[j])
        throw io::CsvError(table.source() + ": signal '" + f.names[i] + "' is asked for twice");
  if (f.names.empty()) {
    // odonata-logger export's own bookkeeping column is not a signal of the vehicle.
    for (const auto& n : table.names())
      if (n != time && n != "seq" && !(options.keep && n == options.keep->signal))
        f.names.push_back(n);
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
  const std::vector<double>* condition =
      options.keep ? &table.Column(options.keep->signal) : nullptr;
  // The window, in the file's own time (before times are counted from the first row sent).
  std::vector<double> times;
  std::vector<std::vector<double>> kept;
  const double t0 = time.empty() ? 0.0 : table.Column(time).front();
  for (std::size_t r = 0; r < rows; ++r) {
    const double t = f.times_s[r] + t0;
    if (t < options.from_s || t > options.to_s) continue;
    std::vector<double> row(f.names.size());
    for (std::size_t c = 0; c < columns.size(); ++c) row[c] = (*columns[c])[r];
    if (condition && !options.keep->Holds((*condition)[r]))
      row.assign(row.size(), std::numeric_limits<double>::quiet_NaN());  // sent as a gap
    times.push_back(f.times_s[r]);
    kept.push_back(std::move(row));
  }
  if (kept.empty())
    throw timeseries::NothingToIdentify(table.source() + ": no row inside the window (from " +
                                        std::to_string(options.from_s) + " s to " +
                                        std::to_string(options.to_s) + " s)");
  if (condition && std::none_of(kept.begin(), kept.end(), [](const std::vector<double>& row) {
        return std::all_of(row.begin(), row.end(), [](double v) { return std::isfinite(v); });
      }))
    throw timeseries::NothingToIdentify(table.source() + ": the condition " +
                                        options.keep->ToString() +
                                        " holds at no row: nothing to send");
  const double first = times.front();
  for (double& t : times) t -= first;
  f.times_s = std::move(times);
  f.rows = std::move(kept);
  return f;
}

}  // namespace odonata::replay

// Fuzz harness: the Crazyflie micro-SD log reader and its signals. Damage after the first 5 bytes
// must end in the file's `problem` (or its notes, for a CRC), what is no such log in
// odonata::crazyflie_usd::UsdLogError (exactly when LooksLikeUsdLog says no), a signal that cannot
// be had in std::invalid_argument: never a crash, undefined behaviour or unbounded memory.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "crazyflie_usd/usd_log_signals.hpp"
#include "timeseries/uniform_grid.hpp"

namespace {

void Check(bool ok) {
  if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace usd = odonata::crazyflie_usd;
  namespace timeseries = odonata::timeseries;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const bool looks_like_one = usd::LooksLikeUsdLog(bytes);
  usd::UsdLogFile file;
  try {
    file = usd::Parse(bytes, "fuzz");
  } catch (const usd::UsdLogError&) {
    Check(!looks_like_one);
    return 0;
  }
  Check(looks_like_one);
  Check(file.complete() == file.problem.empty());
  Check(file.problem_offset <= size);
  Check(file.header_size <= size);
  Check(!file.crc_valid || file.crc_stored == file.crc_computed);
  std::size_t records = 0;
  for (const auto& t : file.event_types) {
    Check(t.values.size() == t.size() * t.variables.size());
    Check(t.variables.size() <= usd::kMaxVariablesPerType);
    records += t.size();
  }
  Check(records == file.records);
  Check(file.event_types.size() <= usd::kMaxEventTypes);
  try {
    const std::vector<usd::SignalInfo> signals = usd::ListSignals(file);
    std::vector<timeseries::TimedSignal> chosen;
    double fastest_hz = 0.0;
    for (std::size_t i = 0; i < signals.size() && chosen.size() < 3; i += 1 + signals.size() / 3) {
      timeseries::TimedSignal s = usd::Extract(file, signals[i].name);
      Check(s.t_s.size() == s.values.size() && s.values.size() == signals[i].samples);
      Check(std::is_sorted(s.t_s.begin(), s.t_s.end()));
      Check(s.interpolation == signals[i].interpolation);
      fastest_hz = std::max(fastest_hz, signals[i].median_rate_hz);
      chosen.push_back(std::move(s));
    }
    if (!chosen.empty()) {
      // The grid spans what the interpolated signals cover (held flags do not bound it), or what
      // all cover when none is interpolated. Its size is bounded here, not only by Resample's
      // limit: a hostile log's times span up to 2^64 µs, and 50 million cells per run would make
      // the campaign crawl.
      const bool any_linear = std::any_of(chosen.begin(), chosen.end(), [](const auto& s) {
        return s.interpolation == timeseries::Interpolation::kLinear;
      });
      double begin_s = -1e300, end_s = 1e300;
      for (const auto& s : chosen) {
        if (any_linear && s.interpolation != timeseries::Interpolation::kLinear) continue;
        begin_s = std::max(begin_s, s.t_s.front());
        end_s = std::min(end_s, s.t_s.back());
      }
      timeseries::GridOptions grid;
      grid.rate_hz = 100.0 / std::max(end_s - begin_s, 1e-3);
      grid.max_cells = 100000;
      if (fastest_hz > 0.0 && end_s > begin_s && (end_s - begin_s) * fastest_hz < 1e5)
        grid.rate_hz = 0.0;
      const timeseries::UniformGrid g = timeseries::Resample(chosen, grid);
      for (const auto& column : g.columns) Check(column.size() == g.t_s.size());
    }
    (void)usd::Extract(file, "no_such.signal");
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

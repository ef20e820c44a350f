// Fuzz harness: the ULog reader (PX4 flight logs) and its signals. Damage after the header must
// end in the file's `problem`, what is no ULog in odonata::ulog::UlogError, a signal that cannot
// be had in std::invalid_argument: never a crash, undefined behaviour or unbounded memory.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

namespace {

void Check(bool ok) {
  if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace ulog = odonata::ulog;
  namespace timeseries = odonata::timeseries;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const ulog::UlogFile file = ulog::Parse(bytes, "fuzz");
    Check(file.complete() == file.problem.empty());
    Check(file.problem_offset <= size);
    for (const auto& s : file.subscriptions) {
      Check(s.data.size() == s.size() * s.layout->logged_size);
      Check(s.first_appended_sample <= s.size());
    }
    for (const auto& [key, value] : file.info) {
      (void)value.Text();
      (void)value.Number();
      (void)value.Integer();
    }
    const std::vector<ulog::SignalInfo> signals = ulog::ListSignals(file);
    std::vector<std::string> names;
    double fastest_hz = 0.0, begin_s = -1e300, end_s = 1e300;
    // The grid spans what the interpolated signals cover (held flags do not bound it), or what
    // all cover when none is interpolated.
    std::vector<std::size_t> chosen;
    for (std::size_t i = 0; i < signals.size() && chosen.size() < 3; i += 1 + signals.size() / 3)
      chosen.push_back(i);
    const bool any_linear = std::any_of(chosen.begin(), chosen.end(), [&](std::size_t i) {
      return signals[i].interpolation == timeseries::Interpolation::kLinear;
    });
    for (const std::size_t i : chosen) {
      const ulog::SignalSamples s = ulog::Extract(file, signals[i].name);
      Check(s.t_s.size() == s.values.size() && s.values.size() == signals[i].samples);
      Check(std::is_sorted(s.t_s.begin(), s.t_s.end()));
      names.push_back(signals[i].name);
      fastest_hz = std::max(fastest_hz, signals[i].median_rate_hz);
      if (any_linear && signals[i].interpolation != timeseries::Interpolation::kLinear) continue;
      begin_s = std::max(begin_s, s.t_s.front());
      end_s = std::min(end_s, s.t_s.back());
    }
    if (!names.empty() && end_s >= begin_s) {
      // The grid's size is bounded here, not only by Resample's limit: a hostile log's times
      // span up to 2^64 µs, and 50 million cells per run would make the campaign crawl.
      if (fastest_hz > 0.0 && (end_s - begin_s) * fastest_hz < 1e5) {
        const ulog::ResampledSignals r = ulog::Resample(file, names, 0.0, 2);
        for (const auto& column : r.columns) Check(column.size() == r.t_s.size());
      }
      // About 100 points (times near 2^64 µs lose their last digits as seconds: a few more).
      const double rate_hz = 100.0 / std::max(end_s - begin_s, 1e-3);
      const ulog::ResampledSignals r = ulog::Resample(file, names, rate_hz, 0);
      Check(r.t_s.size() < 10000 && r.columns.size() == names.size());
    }
    (void)ulog::Extract(file, "no_such_topic.field[0]");
  } catch (const ulog::UlogError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

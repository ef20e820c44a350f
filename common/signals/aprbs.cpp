#include "signals/aprbs.hpp"

#include <cmath>
#include <random>
#include <stdexcept>

namespace odonata::signals {

std::string AprbsProblems(const AprbsOptions& o) {
  std::string p;
  if (!std::isfinite(o.low) || !std::isfinite(o.high) || o.low > o.high)
    p += "APRBS levels need finite low <= high\n";
  if (o.hold_min < 1 || o.hold_max < o.hold_min)
    p += "APRBS holds need 1 <= hold_min <= hold_max samples\n";
  if (o.smooth > 100000) p += "APRBS smoothing longer than 100000 samples\n";
  if (!p.empty()) p.pop_back();
  return p;
}

std::vector<double> AprbsSequence(std::size_t samples, const AprbsOptions& o, std::uint64_t seed) {
  if (const std::string p = AprbsProblems(o); !p.empty()) throw std::invalid_argument(p);
  std::mt19937_64 rng(seed);
  const auto span = static_cast<std::uint64_t>(o.hold_max - o.hold_min) + 1;
  std::vector<double> v;
  v.reserve(samples);
  while (v.size() < samples) {
    // 53 random bits give a uniform double in [0, 1); the modulo's bias is below 2⁻⁴⁰ for any
    // hold span a run can have.
    const double unit = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    const double level = o.low + (o.high - o.low) * unit;
    const std::uint64_t hold = static_cast<std::uint64_t>(o.hold_min) + rng() % span;
    for (std::uint64_t i = 0; i < hold && v.size() < samples; ++i) v.push_back(level);
  }
  if (o.smooth > 1) {
    // Trailing mean over the last `smooth` samples (fewer at the start), summed afresh each time
    // so rounding cannot accumulate over a long run.
    std::vector<double> out(v.size());
    const auto width = static_cast<std::size_t>(o.smooth);
    for (std::size_t k = 0; k < v.size(); ++k) {
      const std::size_t first = k + 1 >= width ? k + 1 - width : 0;
      double sum = 0.0;
      for (std::size_t i = first; i <= k; ++i) sum += v[i];
      out[k] = sum / static_cast<double>(k + 1 - first);
    }
    v = std::move(out);
  }
  return v;
}

}  // namespace odonata::signals

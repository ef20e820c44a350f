#include "timeseries/gap_rule.hpp"

#include <cmath>

namespace odonata::timeseries {

long BridgeRuns(std::vector<double>* values, int max_gap) {
  std::vector<double>& v = *values;
  long filled = 0;
  const auto n = static_cast<long>(v.size());
  long last_good = -1;
  for (long i = 0; i < n; ++i) {
    if (std::isnan(v[static_cast<std::size_t>(i)])) continue;
    const long run = i - last_good - 1;
    if (last_good >= 0 && Bridges(run, max_gap)) {
      const double a = v[static_cast<std::size_t>(last_good)];
      const double b = v[static_cast<std::size_t>(i)];
      for (long k = last_good + 1; k < i; ++k)
        v[static_cast<std::size_t>(k)] = Bridge(a, b, k - last_good, i - last_good);
      filled += run;
    }
    last_good = i;
  }
  return filled;
}

}  // namespace odonata::timeseries

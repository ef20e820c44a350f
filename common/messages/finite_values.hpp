#pragma once

#include <cmath>

namespace odonata::messages {
// Whether the n values a message's fixed array holds are all finite: a decoded message with a NaN
// or an infinity is dropped and counted, never applied (docs/lcm.md).
inline bool FiniteValues(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
}  // namespace odonata::messages

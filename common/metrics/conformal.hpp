#pragma once
// The split-conformal half width (docs/identifier.md §7.6): one rule for odonata-fit's intervals
// (fit/prediction_intervals) and the online identifier's live ones (sysid/online/live_intervals).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace odonata::metrics {

/// Of n absolute residuals |e| (finite), the ⌈(n + 1)·level⌉-th smallest: for a new residual
/// exchangeable with them, |e| ≤ it with probability ≥ level. +∞ when that rank exceeds n (too
/// few residuals for the level). Reorders `abs_residuals`. @pre 0 < level < 1.
inline double ConformalHalfWidth(std::vector<double>& abs_residuals, double level) {
  const auto n = static_cast<double>(abs_residuals.size());
  const auto k = static_cast<std::size_t>(std::ceil((n + 1.0) * level));
  if (abs_residuals.empty() || k > abs_residuals.size())
    return std::numeric_limits<double>::infinity();
  const auto kth = abs_residuals.begin() + static_cast<std::ptrdiff_t>(k - 1);
  std::nth_element(abs_residuals.begin(), kth, abs_residuals.end());
  return *kth;
}

}  // namespace odonata::metrics

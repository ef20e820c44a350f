#pragma once
// Split-conformal prediction intervals (docs/identifier.md §7.6): the half width, one rule for
// odonata-fit's intervals (fit/prediction_intervals) and the online identifier's live ones
// (sysid/online/live_intervals); and how often an interval covered, for odonata-fit's scores and
// the monitor's alike.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include <nlohmann/json.hpp>

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

/// How often the measured value fell within ŷ ± half width, and the interval's mean width
/// (2 × half width), over the samples whose interval was known (half width ≥ 0; −1 or NaN: not
/// known, not counted). A prediction that is not finite is counted and not covered.
struct IntervalTally {
  int64_t scored = 0, covered = 0;
  double width_sum = 0.0;
  void Add(double measured, double predicted, double half_width) {
    if (!(half_width >= 0.0)) return;
    ++scored;
    if (std::isfinite(predicted) && std::abs(measured - predicted) <= half_width) ++covered;
    width_sum += 2.0 * half_width;
  }
  double coverage() const { return scored > 0 ? static_cast<double>(covered) / scored : 0.0; }
  double mean_width() const { return scored > 0 ? width_sum / static_cast<double>(scored) : 0.0; }
  /// {coverage, mean_width (null when infinite), samples}
  nlohmann::json ToJson() const {
    const double w = mean_width();
    return {{"coverage", coverage()},
            {"mean_width", std::isfinite(w) ? nlohmann::json(w) : nlohmann::json()},
            {"samples", scored}};
  }
};

}  // namespace odonata::metrics

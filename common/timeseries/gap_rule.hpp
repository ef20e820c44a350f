#pragma once
// The gap rule for samples that come one per grid step (a CSV row, a live sample): a run of at
// most max_gap missing samples between two present ones is bridged by the straight line between
// them; a longer run (or one at either end) stays missing, and the reader splits the data there.
// One home, so that odonata-fit's reading of a log and the live identifier learn the same values.

#include <cstdint>
#include <vector>

namespace odonata::timeseries {

/// The value k steps after `a` on the straight line to `b`, which is `span` steps after `a`
/// (0 < k < span): the arithmetic every bridged sample is made with (a scalar or an Eigen vector,
/// element by element the same).
template <class T>
T Bridge(const T& a, const T& b, std::int64_t k, std::int64_t span) {
  const double w = static_cast<double>(k) / static_cast<double>(span);
  return a + w * (b - a);
}

/// Whether a run of `missing` samples is short enough to bridge.
inline bool Bridges(std::int64_t missing, int max_gap) { return missing > 0 && missing <= max_gap; }

/// Fills every interior run of at most `max_gap` NaNs by Bridge between its neighbours; longer
/// runs, and runs at either end, stay NaN. Returns the cells filled.
long BridgeRuns(std::vector<double>* values, int max_gap);

}  // namespace odonata::timeseries

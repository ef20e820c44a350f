#pragma once
// Declared signal ranges, for online identification where the data is not known in advance
// (docs/identifier.md §7). The same file drives odonata-fit --ranges, so offline and online models
// use identical scaling.

#include <map>
#include <string>
#include <utility>

#include <nlohmann/json_fwd.hpp>

#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/scaling.hpp"

namespace odonata::sysid {

/// name → [min, max], raw units.
using SignalRanges = std::map<std::string, std::pair<double, double>>;

/// Every regressor of a signal gets that signal's range mapped to [−1, 1]; an output is
/// standardised with mean (min+max)/2 and std (max−min)/2.
/// @throws std::runtime_error naming a signal with no range, or with max ≤ min.
Scaling ScalingFromRanges(const RegressorSpec& spec, const SignalRanges& ranges);

/// Ranges observed in a series (for the spec's outputs and inputs).
SignalRanges RangesFromSeries(const RegressorSpec& spec, const Series& series);

/// {"roll_rad": [-0.5, 0.5], ...}
nlohmann::json RangesToJson(const SignalRanges& ranges);
/// @throws std::runtime_error on malformed content.
SignalRanges RangesFromJson(const nlohmann::json& j);

}  // namespace odonata::sysid

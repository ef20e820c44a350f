#pragma once
// What the online identifier's tests feed it: a series' rows as samples, and an empty model
// scaled to the series' signal ranges (as an identifier configuration declares them).

#include "narendra_series.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::sysid::testing {

inline Sample Row(const Series& s, Eigen::Index k) {
  return {k, s.outputs.row(k).transpose(), s.inputs.row(k).transpose()};
}

inline NarxModel Empty(fuzzy::ConsequentKind kind, const Series& train) {
  fuzzy::FuzzyModelConfig cfg;
  cfg.consequent = kind;
  NarxModel m(NarendraSpec(), cfg);
  m.SetScaling(ScalingFromRanges(m.spec(), RangesFromSeries(m.spec(), train)));
  return m;
}

}  // namespace odonata::sysid::testing

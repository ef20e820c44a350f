#pragma once
// Whether a training series holds anything to identify, checked before any fit: a signal that
// never moves, an output quantised to a few levels, a series too short for its lags and horizon,
// and a hold-out too small to choose settings on. A fatal finding is thrown as NothingToIdentify
// with what to do; the others are warnings.
//
// Bounds (docs/guide/offline-tool.md, "Nothing to identify"):
//  - constant: max − min ≤ 1e-9 · max(|max|, |min|), or exactly equal values.
//  - quantised output: 5 distinct values or fewer (a warning).
//  - too short: fewer targets than 2 · regressors + horizon.
//  - hold-out too small: fewer than max(20, 3 · regressors) targets to choose settings on.

#include <string>
#include <vector>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

struct SignalExcitation {
  std::string name;
  bool output = false;
  double min = 0, max = 0, std = 0;
  long levels = 0;  ///< distinct values, counted up to 1000
  bool constant = false;
};

struct ExcitationReport {
  std::vector<SignalExcitation> signals;
  long targets = 0;          ///< rows with a complete regressor
  long holdout_targets = 0;  ///< of them, what settings are chosen on (0: no choice)
  std::vector<std::string> warnings;
};

struct ExcitationNeeds {
  int horizon = 0;                ///< K of a K-step score (0: none)
  double holdout_fraction = 0.0;  ///< settings chosen on this last part (0: no choice)
  long holdout_targets = -1;      ///< or on this many targets of another file (-1: none)
};

/// Checks `train` for `spec`. `source` names the data in messages.
/// @throws NothingToIdentify saying what is wrong and what to do.
ExcitationReport CheckExcitation(const RegressorSpec& spec, const Series& train,
                                 const ExcitationNeeds& needs, const std::string& source);

}  // namespace odonata::sysid

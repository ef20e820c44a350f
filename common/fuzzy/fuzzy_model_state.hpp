#pragma once
// A fuzzy model's whole state as plain data: what a saved model file and a bus snapshot both
// carry. FuzzyModel::State() fills it and FuzzyModel::FromState() is the one place that checks it,
// so a model file (JSON) and a snapshot (LCM arrays) are two encodings of the same thing, each
// converted directly, and validated alike.

#include <cstdint>
#include <vector>

#include "fuzzy/consequent.hpp"
#include "fuzzy/fuzzy_model.hpp"
#include "fuzzy/rule_names.hpp"

namespace odonata::fuzzy {

/// One rule's antecedent (scaled units) and its housekeeping (docs/identifier.md §5).
struct RuleState {
  std::vector<double> centre, sigma;  ///< one per input
  double output_width = 0;
  double utility_sum = 0;  ///< Σ φ_j since the rule's creation
  int64_t born = 0;        ///< the model's clock when the rule was created
  RuleNames names;
};

/// The consequents and their learners' state, rule by rule.
struct ConsequentState {
  ConsequentKind kind = ConsequentKind::kSingleton;
  double rate = 0, regulariser = 0;               ///< singleton NLMS (0 for linear)
  double initial_covariance = 0, forgetting = 1;  ///< linear RLS (unused for singletons)
  std::vector<std::vector<double>> coefficients;  ///< per rule: 1 value, or inputs + 1
  std::vector<std::vector<double>> covariances;   ///< per rule: (inputs + 1)² (linear only)
};

struct FuzzyModelState {
  FuzzyModelConfig config;
  int64_t clock = 0;   ///< samples seen in rule-growing mode
  int64_t pruned = 0;  ///< rules removed so far
  std::vector<RuleState> rules;
  ConsequentState consequent;
};

}  // namespace odonata::fuzzy

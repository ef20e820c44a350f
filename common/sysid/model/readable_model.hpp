#pragma once
// A model a drone operator reads (docs/identifier.md §7.5): per signal at most five shared, named
// terms (very low … very high) instead of a Gaussian per rule and lag; a rule's lags of one
// signal read as one clause; rules whose premises map onto the same terms are one rule; a signal
// whose term is the same in every rule drops out (it does not change any output); and a model
// whose rules' local models coincide is "linear: one rule". The readable form is itself a model —
// the shared terms are its premises and its consequents are fitted again on the training data by
// least squares — so it predicts and is scored beside the full model: its cost is a FIT figure.

#include <string>
#include <vector>

#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

struct ReadableOptions {
  /// Two rules' local models coincide when their scaled coefficients differ by at most this in
  /// sum: on regressors within the training range (|x| ≤ 1 scaled) their predictions differ by at
  /// most 1 % of the output's standard deviation, below what any FIT figure shows.
  double coincide = 0.01;
  /// The mode the full model was chosen in (its consequents' choice between the rules' own and
  /// least squares is made in it, on the training data): K > 1 steps ahead, else free run (one
  /// step without output lags).
  int criterion_horizon = 0;
  /// At most this many readable rules per output (a person takes in about seven at once): beyond
  /// it, signals leave every rule's premise, the cheapest first (MakeReadable).
  int max_rules = 7;
};

struct ReadableModel {
  NarxModel model;
  /// Per output, its rules as sentences, then one line per signal kept: its terms' centres and
  /// widths in raw units.
  std::vector<std::vector<std::string>> sentences;
  /// Per output, whether the full model's local models all coincided (one linear rule).
  std::vector<bool> linear;
};

/// The readable form of `full`, its consequents fitted on `train` (the series the full model was
/// trained on); `sample_time_s` as for DescribeRules (0: time in samples).
/// @throws std::invalid_argument when `train` is too short for the regressor.
ReadableModel MakeReadable(const NarxModel& full, const Series& train, double sample_time_s = 0,
                           const ReadableOptions& options = {});

/// At most this many shared terms per signal: very low, low, medium, high, very high.
inline constexpr int kReadableTerms = 5;

}  // namespace odonata::sysid

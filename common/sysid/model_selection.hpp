#pragma once
// Choosing the consequent kind, H̄, the width factor κ and the epoch count on a hold-out slice of
// the training data, by simulation accuracy (docs/identifier.md §9). The validation data never
// takes part in a choice.

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "sysid/narx_model.hpp"

namespace odonata::sysid {

enum class SelectionCriterion {
  kAuto,     ///< free-run NDEI when the model has output lags, else one-step
  kFreeRun,  ///< free-run NDEI (simulation accuracy)
  kOneStep,  ///< one-step NDEI (static maps, integrating loops whose free run drifts)
};

struct SelectionOptions {
  std::vector<fuzzy::ConsequentKind> consequents;  ///< empty: linear and singleton
  std::vector<double> thresholds;                  ///< H̄ values; empty: DefaultThresholds()
  std::vector<double> kappas;                      ///< κ values; empty: DefaultKappas()
  int max_epochs = 50;            ///< per candidate; the best hold-out epoch is kept
  int patience = 10;              ///< stop a candidate after this many epochs without improvement
  double holdout_fraction = 0.2;  ///< the last part of the training series
  SelectionCriterion criterion = SelectionCriterion::kAuto;
  /// The fewest rules whose score is within max(best × (1 + relative), best + absolute): NDEI
  /// differences below the absolute one (half a FIT point) do not pay for more rules.
  double relative_tolerance = 0.05;
  double absolute_tolerance = 0.005;
  /// Declared scaling (the online identifier's ranges): candidates learn with it, as the final
  /// model will. Empty: each candidate fits its scaling on the data it trains on.
  std::optional<Scaling> scaling;
};

struct Candidate {
  fuzzy::ConsequentKind consequent = fuzzy::ConsequentKind::kLinear;
  double threshold = 0.0;
  double kappa = 0.0;
  int epochs = 0;  ///< the epoch kept by the hold-out
  int rules = 0;
  bool at_cap = false;
  double holdout_one_step_ndei = 0.0;
  double holdout_free_run_ndei = 0.0;  ///< NaN without output lags
  double score = 0.0;                  ///< the criterion's NDEI (+∞ if diverged)
};

struct SelectionResult {
  std::vector<Candidate> candidates;
  std::size_t best = 0;    ///< lowest score
  std::size_t chosen = 0;  ///< fewest rules within the tolerance of the best
  bool free_run_criterion = false;
  Eigen::Index fit_samples = 0;
  Eigen::Index holdout_samples = 0;
  std::vector<std::string> warnings;  ///< the search's edge, the rule cap, the epoch limit
};

/// Novelty radius r (distance from the nearest rule, in its widths, per input) → H̄ with the
/// per-input firing measure: H(exp(−r²/2)).
double ThresholdForRadius(double radius);
/// H̄ for radii 2.0 … 0.5 widths: evenly spread in what they mean, not in H̄ (which is flat
/// near its maximum).
std::vector<double> DefaultThresholds();
std::vector<double> DefaultKappas();

/// Rows [begin, begin + count) of a series.
Series SliceSeries(const Series& s, Eigen::Index begin, Eigen::Index count);

/// Trains every candidate on the first (1 − holdout_fraction) of `train` and scores it on the
/// rest — or, when `selection` is given (a separate selection excitation), on all of `train`
/// and scores it on `selection`. H̄ is tried from low to high for each (consequent, κ); once a
/// candidate reaches the rule cap the higher H̄ of that pair are skipped (they would reach it too).
/// `train_options.epochs` is ignored (options.max_epochs rules); its hold-out fields are set here.
/// @throws std::invalid_argument when the slices are too short for the lags.
SelectionResult SelectModel(
    const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
    const TrainOptions& train_options, const Series& train, const SelectionOptions& options,
    const std::function<void(const Candidate&, std::size_t, std::size_t)>& on_candidate = {},
    const Series* selection = nullptr);

}  // namespace odonata::sysid

#pragma once
// How a NARX model is trained offline, and what the training reports (narx_training.hpp): the
// estimation's own types, kept out of the model (sysid/model/), which knows nothing of how it is
// estimated.

#include <atomic>
#include <functional>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid {

/// One stage of simulation-error training (simulation_error_training.hpp).
struct SimulationStage {
  int horizon = 20;  ///< samples per shooting window
  int steps = 30;    ///< iRprop− steps at most (Levenberg–Marquardt iterations with the flag)
  /// Levenberg–Marquardt on the consequents alone (premises fixed), through the forward
  /// sensitivities of the recursion, instead of iRprop− on every parameter: for the linear
  /// model, whose few parameters it takes to the output-error optimum in a few iterations
  /// (docs/identifier.md §12).
  bool gauss_newton = false;
  /// With gauss_newton: every rule's consequent is first set to the global linear model's (one
  /// shared consequent, from its one-step least squares), and the iterations move that shared
  /// consequent only: the fuzzy model leaves this stage as the linear model's output-error fit,
  /// a start for the stages after it (docs/identifier.md §12). Linear consequents only; on any
  /// other model the stage does nothing.
  bool from_linear = false;
  bool operator==(const SimulationStage& o) const {
    return horizon == o.horizon && steps == o.steps && gauss_newton == o.gauss_newton &&
           from_linear == o.from_linear;
  }
};

/// Reports (epoch, sample, samples per epoch) during training; may be empty.
using ProgressCallback = std::function<void(int epoch, long sample, long total)>;

struct TrainOptions {
  /// Passes over the data: the first grows rules, later ones only tune. From the second on, a
  /// pass that raises the training loss is rejected (parameters restored, premise rate halved);
  /// an accepted one raises the rate by 10 % (docs/identifier.md §6.2).
  int epochs = 1;
  /// After each pass, solve every consequent by global least squares with the antecedents
  /// fixed (ANFIS's hybrid rule). Offline only: the online identifier cannot revisit the past.
  bool refine_least_squares = true;
  /// Least-squares ridge, relative to the mean squared column norm of the design.
  double ridge = 1e-10;
  /// Ridge on each rule's deviation from one global linear model (FuzzyModel::RefineConsequents);
  /// 0: none.
  double deviation_ridge = 0.0;
  /// With least squares, after the pass that grows rules: a rule whose support (normalised firing
  /// summed over the training rows) is below this many times its consequent's parameter count is
  /// removed (FuzzyModel::PruneUnsupported): the solve cannot determine it; 0: none.
  double min_rule_support = 1.0;
  /// Find the outputs' saturation limits in the training data and hold every prediction to them
  /// (OutputLimits; the last training's data decides). False keeps the limits the model has.
  bool detect_output_limits = true;
  /// Derive the scaling from the training data (offline default). False keeps the scaling set
  /// by SetScaling(), as the online identifier must: then offline and online agree bit for bit.
  bool fit_scaling = true;
  /// False: the first pass only tunes, no rule is created — the rule base was grown already
  /// (on blocks spread over a long record, offline_fit.cpp).
  bool grow_rules = true;
  /// Optional hold-out slice of the training data: the epoch with the lowest hold-out NDEI is the
  /// one kept. Free-run NDEI when the model has output lags and holdout_free_run is set, else
  /// one-step.
  const Series* holdout = nullptr;
  bool holdout_free_run = true;
  /// > 0: the hold-out is scored this many steps ahead instead (integrating loops, whose free
  /// run drifts for any model).
  int holdout_horizon = 0;
  /// With a hold-out scored ahead or in free run: a pass (or a simulation step) is kept only while
  /// its one-step hold-out NDEI is at most this. The selection sets it for a K-step score, from
  /// the linear model's (docs/identifier.md §9): a loop scored K steps ahead is reported one step
  /// ahead too.
  double holdout_one_step_bound = std::numeric_limits<double>::infinity();
  /// With a hold-out: stop after this many passes without a hold-out improvement (0: never).
  int patience = 0;
  /// After the one-step passes: iRprop− steps on the multiple-shooting simulation error, stage
  /// by stage (simulation_error_training.hpp; with a hold-out, the step it scores best in free run
  /// is kept). Empty: none; ignored without output lags.
  std::vector<SimulationStage> simulation;
  /// After training, find where the training rows end and fit the global linear model the
  /// predictions blend into beyond them (DataEnvelope). A selection's candidates are scored
  /// without it; the final model of a fit has it.
  bool fit_envelope = false;
  ProgressCallback progress;
  /// The simulation-error stages after the passes: (stage, steps done, steps of every stage) —
  /// each step about the same work (every window is simulated once a step).
  ProgressCallback simulation_progress;
  /// When set and true, training stops by throwing TrainingCancelled at the next pass or
  /// simulation step (a refit the identifier no longer needs, at shutdown).
  const std::atomic<bool>* cancel = nullptr;
};

/// Thrown by NarxModel::Train when TrainOptions::cancel is raised.
struct TrainingCancelled : std::runtime_error {
  TrainingCancelled() : std::runtime_error("training cancelled") {}
};

/// What one training pass did.
struct EpochRecord {
  int epoch = 0;            ///< 1-based
  bool accepted = true;     ///< false: the pass raised the training loss and was undone
  double rate_scale = 1.0;  ///< premise-rate multiplier the pass ran with
  double train_fit = 0.0;   ///< one-step training FIT % (mean over outputs) after the pass
  double holdout_ndei = std::numeric_limits<double>::quiet_NaN();  ///< when a hold-out is given
  int rules = 0;
};

struct TrainReport {
  std::vector<EpochRecord> epochs;
  int kept_epoch = 0;  ///< the epoch whose parameters the model holds (1-based)
  /// Rules the growing pass created (over outputs), before the unsupported ones were removed
  /// (TrainOptions::min_rule_support): a candidate that grew to the cap reached it, even if
  /// pruning then took it below.
  int rules_grown = 0;
  /// The simulation-error schedule that reproduces the kept parameters without a hold-out.
  std::vector<SimulationStage> simulation;
};

}  // namespace odonata::sysid

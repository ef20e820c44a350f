#pragma once
// Choosing the consequent kind, H̄, the width factor κ and the epoch count on a hold-out slice of
// the training data, by simulation accuracy (docs/identifier.md §9). The validation data never
// takes part in a choice.

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

enum class SelectionCriterion {
  kAuto,     ///< free-run NDEI when the model has output lags, else one-step
  kFreeRun,  ///< free-run NDEI (simulation accuracy)
  kOneStep,  ///< one-step NDEI (static maps, integrating loops whose free run drifts)
  kAhead,    ///< NDEI `horizon` steps ahead (integrating loops: a short horizon)
};

struct SelectionOptions {
  std::vector<fuzzy::ConsequentKind> consequents;  ///< empty: linear and singleton
  std::vector<double> thresholds;                  ///< H̄ values; empty: DefaultThresholds()
  std::vector<double> kappas;                      ///< κ values; empty: DefaultKappas()
  int max_epochs = 50;            ///< per candidate; the best hold-out epoch is kept
  int patience = 10;              ///< stop a candidate after this many epochs without improvement
  double holdout_fraction = 0.2;  ///< the last part of the training series
  SelectionCriterion criterion = SelectionCriterion::kAuto;
  /// K > 1: every candidate is also scored K steps ahead, and kAuto chooses by it (what the user
  /// reports for a loop whose free run drifts); 0: no k-step score.
  int horizon = 0;
  /// The fewest rules whose score is within max(best × (1 + relative), best + absolute): NDEI
  /// differences below the absolute one (half a FIT point) do not pay for more rules.
  double relative_tolerance = 0.05;
  double absolute_tolerance = 0.005;
  /// The one-rule linear model (ARX on the same regressor) is a candidate whenever linear
  /// consequents are (and H̄ is searched). A fuzzy model chosen over it must then also beat it in
  /// blocked cross-validation over this many contiguous folds of the training series, each scored
  /// by the criterion after training on the others: one tail slice is too few samples to trust
  /// on a short or drifting record (docs/identifier.md §9). < 2: no cross-validation.
  int linear_check_folds = 4;
  /// How many fuzzy candidates may face that cross-validation: the chosen one, then, while each
  /// loses, the next by hold-out score. One hold-out slice ranks candidates whose free runs are
  /// fragile (the Silverbox's: three folds 4–6× better than ARX, the fourth diverged) no better
  /// than it ranks a stable one a little behind them. Each beats ARX by the same margin or none is
  /// kept.
  int linear_check_candidates = 3;
  /// Simulation-error training (simulation_error_training.hpp) of the short list — the
  /// `simulation_shortlist` best fuzzy candidates, and with a K-step criterion the linear model —
  /// after their one-step training, the hold-out keeping the best step; then they are scored
  /// again. Windows no longer than K with a K-step criterion; none with the one-step criterion.
  /// In free run the linear model takes Levenberg–Marquardt to its output-error fit instead, and
  /// the folds choose between that and least squares. Empty: none.
  std::vector<SimulationStage> simulation;
  int simulation_shortlist = 3;
  /// With the free-run criterion, the short list's fuzzy candidates also end their simulation
  /// training with Levenberg–Marquardt on all their parameters (the consequents alone for a large
  /// rule base) over the longest windows, as the linear model's output-error fit does
  /// (docs/identifier.md §12).
  bool fuzzy_output_error = true;
  /// The short list's fuzzy candidates with linear consequents are also trained from the linear
  /// model's fit of the longest windows (SimulationStage::from_linear), each a candidate of its
  /// own (docs/identifier.md §12).
  bool restart_from_linear = true;
  /// Shrinkage toward the global linear model (TrainOptions::deviation_ridge): the
  /// `ridge_shortlist` best fuzzy candidates with linear consequents are trained again with each
  /// of these ridges (for no more epochs than they kept unshrunk), each a candidate of its own,
  /// so the hold-out (and the cross-validation) chooses how far a noisy record's rules may leave
  /// ARX. Empty: every candidate trains with the training options' ridge (given on the command
  /// line).
  std::vector<double> deviation_ridges = {0.01, 0.1, 1.0};
  int ridge_shortlist = 1;
  /// Threads for the independent trainings (the (consequent, κ) sweeps, the short list, the
  /// folds); 0: every core. The result does not depend on it, bit for bit.
  unsigned threads = 0;
  /// Declared scaling (the online identifier's ranges): candidates learn with it, as the final
  /// model will. Empty: each candidate fits its scaling on the data it trains on.
  std::optional<Scaling> scaling;
};

/// What a candidate's training took, on the fit slice and one thread: for a fit's time-left
/// estimate only (EstimateFinalTraining) — wall time varies run to run and chooses nothing.
struct TrainingCost {
  int epochs_run = 0;            ///< the growing pass and the epochs, each scored on the hold-out
  double epochs_seconds = 0.0;   ///< their wall time
  int simulation_steps_run = 0;  ///< simulation-error steps, the ones the hold-out refused too
  double simulation_seconds = 0.0;
};

struct Candidate {
  fuzzy::ConsequentKind consequent = fuzzy::ConsequentKind::kLinear;
  /// The one-rule linear model: trained with max_rules = 1 (threshold 0), it is ARX.
  bool linear = false;
  double threshold = 0.0;
  double kappa = 0.0;
  /// Ridge on the rules' deviation from the global linear model (TrainOptions::deviation_ridge).
  double deviation_ridge = 0.0;
  int epochs = 0;  ///< the epoch kept by the hold-out
  /// The simulation-error schedule the kept parameters took (empty: none).
  std::vector<SimulationStage> simulation;
  int rules = 0;
  bool at_cap = false;
  double holdout_one_step_ndei = 0.0;
  double holdout_free_run_ndei = 0.0;  ///< NaN without output lags
  double holdout_ahead_ndei = 0.0;     ///< K steps ahead (SelectionOptions::horizon), else NaN
  double score = 0.0;                  ///< the criterion's NDEI (+∞ if diverged)
  /// Free-run criterion only: how far the model is from rest after being held at the training
  /// file's mean input (RestDeviation); NaN when not tested.
  double rest_deviation = std::numeric_limits<double>::quiet_NaN();
  /// It does not come to rest where the linear model does: a self-excited oscillation the
  /// hold-out may not show (score +∞).
  bool restless = false;
  /// K-step criterion: one step ahead on the hold-out it is worse than the linear model by more
  /// than the candidates' margin (SelectionResult::one_step_bound; score +∞).
  bool one_step_lost = false;
  TrainingCost cost;  ///< not reported: it varies run to run
};

/// The blocked cross-validation between the chosen fuzzy setting and the linear model.
struct LinearCheck {
  bool done = false;
  std::size_t candidate = 0;                      ///< the fuzzy candidate checked (its index)
  std::vector<double> fuzzy_folds, linear_folds;  ///< each fold's score (criterion NDEI)
  double fuzzy_score = 0.0, linear_score = 0.0;   ///< their means (+∞ if one diverged)
  /// What the fuzzy mean must beat the linear one by: the absolute tolerance, or the standard
  /// error of the folds' paired differences when larger.
  double margin = 0.0;
  bool linear_chosen = false;  ///< the fuzzy model did not beat it
};

/// A selection's progress, reported as candidates are trained.
struct SelectionProgress {
  /// Of the selection's work done (each step weighted by its share of a search's time,
  /// docs/reference/benchmarks.md).
  double fraction = 0.0;
  /// The candidate the selection would choose among those trained so far (the best score, then
  /// the fewest rules within its tolerance), and the rows it trained on: the final training's
  /// cost is estimated from its (EstimateFinalTraining).
  Candidate leading;
  Eigen::Index fit_rows = 0;
  /// The seconds the final training is expected to take after the selection: set by FitOffline,
  /// which knows the rows it trains on (0 from SelectModel alone).
  double final_seconds = 0.0;
};

/// Called as candidates are trained: the candidate just trained and the selection's progress.
using CandidateProgress = std::function<void(const Candidate&, const SelectionProgress&)>;

struct SelectionResult {
  std::vector<Candidate> candidates;
  std::size_t best = 0;    ///< lowest score
  std::size_t chosen = 0;  ///< fewest rules within the tolerance of the best
  bool free_run_criterion = false;
  int criterion_horizon = 0;  ///< what the score is: 0 free run, 1 one step, K steps ahead
  Eigen::Index fit_samples = 0;
  Eigen::Index holdout_samples = 0;
  /// K-step criterion: the one-step hold-out NDEI no candidate may exceed — the linear model's
  /// (one-step least squares) plus the candidates' margin; +∞ in free run, one step ahead (the
  /// score itself) or without a linear candidate.
  double one_step_bound = std::numeric_limits<double>::infinity();
  std::vector<std::string> warnings;  ///< the search's edge, the rule cap, the epoch limit
  LinearCheck linear_check;  ///< the check that decided: the winner's, or else the first one's
  /// Every check in the order made (the fuzzy candidates that lost, then the winner if any).
  std::vector<LinearCheck> linear_checks;
  /// Free-run criterion: the linear model's output-error fit (Levenberg–Marquardt, "fuzzy" in
  /// the check) against least squares ("linear") over the same folds; the output-error fit is
  /// kept when it wins (output_error_linear).
  LinearCheck output_error_check;
  bool output_error_linear = false;
  /// The chosen candidate's own model, as the hold-out judged it (trained on the fit slice): the
  /// fallback when the same setting trained on every row is not the same dynamical system.
  std::optional<NarxModel> chosen_model;
};

/// Novelty radius r (distance from the nearest rule, in its widths, per input) → H̄ with the
/// per-input firing measure: H(exp(−r²/2)).
double ThresholdForRadius(double radius);
/// H̄ for radii 2.0 … 0.5 widths: evenly spread in what they mean, not in H̄ (which is flat
/// near its maximum).
std::vector<double> DefaultThresholds();
std::vector<double> DefaultKappas();

/// Held at the mean input of `train`, started from its mean outputs nudged by a tenth of their
/// deviation, the model runs free for as many samples as `train` has (1 000 … 10 000): the
/// deviation of the last quarter of that run over the outputs' deviation (mean over outputs;
/// +∞ if it diverged). A model of a system at rest that oscillates by itself scores high.
double RestDeviation(const NarxModel& model, const Series& train);
/// A model whose RestDeviation is this is not at rest where the linear model (its deviation
/// `linear_rest`) is: a self-excited oscillation.
bool Restless(double rest_deviation, double linear_rest);
/// A score beats another by the margin a candidate needs over a simpler one: lower by more than
/// options.relative_tolerance of it and by more than options.absolute_tolerance.
bool BeatsByMargin(double challenger, double incumbent, const SelectionOptions& options);

/// What the warnings call the linear model a selection keeps: "its output-error fit" when the
/// folds kept that fit (output_error_linear), else "ARX".
const char* LinearFitName(const SelectionResult& result);

/// Every output's rule base has the same rules, centres, widths and output widths, bit for bit.
/// A restart from the linear model's fit (docs/identifier.md §12) sets every consequent, so two
/// models with the same premises restart into the same model.
bool SamePremises(const NarxModel& a, const NarxModel& b);

/// The standard error of the mean of the paired differences b − a over folds: what a mean
/// difference between two settings scored on the same folds must exceed to be more than
/// chance. 0 with fewer than two folds or a non-finite score (the means decide alone).
double PairedStandardError(const std::vector<double>& a, const std::vector<double>& b);

/// Rows [begin, begin + count) of a series.
Series SliceSeries(const Series& s, Eigen::Index begin, Eigen::Index count);
/// A training series cut where a selection's hold-out begins: its last `holdout_samples` rows (at
/// most all of them), where the candidates are judged, and the rows before, where they train.
struct HoldoutSplit {
  Series fit, holdout;
};
HoldoutSplit SplitAtHoldout(const Series& train, Eigen::Index holdout_samples);
/// `a` then `b`, with a break between them (no regressor or free run crosses the seam).
Series ConcatSeries(const Series& a, const Series& b);
/// The model configuration a candidate stands for (`base` with its consequent, H̄, κ and, for
/// the linear candidate, one rule).
fuzzy::FuzzyModelConfig CandidateConfig(const fuzzy::FuzzyModelConfig& base, const Candidate& c);

/// Trains every candidate on the first (1 − holdout_fraction) of `train` and scores it on the
/// rest — or, when `selection` is given (a separate selection excitation), on all of `train`
/// and scores it on `selection`. H̄ is tried from low to high for each (consequent, κ); once a
/// candidate reaches the rule cap the higher H̄ of that pair are skipped (they would reach it too).
/// `train_options.epochs` is ignored (options.max_epochs rules); its hold-out fields are set here.
/// @throws std::invalid_argument when the slices are too short for the lags.
SelectionResult SelectModel(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
                            const TrainOptions& train_options, const Series& train,
                            const SelectionOptions& options,
                            const CandidateProgress& on_candidate = {},
                            const Series* selection = nullptr);

}  // namespace odonata::sysid

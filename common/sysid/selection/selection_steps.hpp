#pragma once
// The steps SelectModel is made of, shared by its files (candidates.cpp, linear_check.cpp,
// simulation_shortlist.cpp, model_selection.cpp): internal to selection/, not an interface.
//
// A selection is a context (the problem, its settings and its slices, fixed once the linear
// model has set the one-step bound) and a state the steps build up in order: the candidates and
// their models, then the short list trained on the simulation error, then the choice and its
// checks against the linear model.

#include <algorithm>
#include <chrono>
#include <cstddef>
#include <functional>
#include <mutex>
#include <optional>
#include <vector>

#include "sysid/estimation/train_options.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

/// Levenberg–Marquardt iterations at most for a model's output-error fit (the linear model
/// converges in far fewer).
inline constexpr int kOutputErrorIterations = 50;

/// What every step of one selection reads: the problem, the settings and the data's slices.
struct SelectionContext {
  const RegressorSpec& spec;
  const fuzzy::FuzzyModelConfig& base;
  const SelectionOptions& options;
  /// The candidates' training; holds the one-step bound once the linear model has set it.
  TrainOptions train_options;
  const Series& train;      ///< the whole training series: the folds' source
  const Series* selection;  ///< a separate selection excitation, or null (a hold-out slice)
  Series fit;               ///< what candidates train on
  Series holdout;           ///< what they are scored on
  int horizon = 0;          ///< the criterion: 0 free run, 1 one step, K steps ahead
  std::vector<fuzzy::ConsequentKind> kinds;
  std::vector<double> thresholds;  ///< ascending
  std::vector<double> kappas;
};

/// What the steps build up: the candidates (in `result`), each one's model at the same index,
/// the linear model's place and its fold scores once known, and the progress reported.
struct SelectionState {
  SelectionResult result;
  std::vector<NarxModel> models;
  std::optional<std::size_t> linear_index;
  std::vector<double> linear_folds;
  /// Progress in work units (PlanProgress): `done` of `total`, reported as a fraction.
  double done = 0.0;
  double total = 0.0;
  CandidateProgress on_candidate;
  /// What the leading candidate is judged by (its tolerance) and trained on.
  const SelectionOptions* options = nullptr;
  Eigen::Index fit_rows = 0;
  /// Reports `c` with the leading candidate among those trained so far (a retrained one replaces
  /// its earlier self), or with `chosen` when the choice is made.
  void Report(const Candidate& c, const Candidate* chosen = nullptr);
  /// The whole done, the choice made: the last report, `chosen` leading.
  void Finish(const Candidate& chosen) {
    done = total;
    Report(chosen, &chosen);
  }
  /// Advances to `mark` (a step's planned end) unless already past it, and reports.
  void ReachMark(double mark, const Candidate& c) {
    done = std::max(done, mark);
    Report(c);
  }
  /// The ridge variants' and the short list's planned ends in work units (set by SelectModel);
  /// the folds end at `total`.
  double ridge_mark = 0.0, shortlist_mark = 0.0;
  /// Advances by `units` and reports, from a step's parallel jobs (one at a time).
  void Advance(double units, const Candidate& c) {
    const std::lock_guard<std::mutex> lock(progress_mutex);
    done += units;
    Report(c);
  }
  std::mutex progress_mutex;

 private:
  std::vector<Candidate> trained_;  // for the leading one; progress only
};

/// The best-scoring candidate (lowest score), and the one chosen: the fewest rules within the
/// tolerance of the best (the better score among equals). {0, 0} when there are none.
struct Choice {
  std::size_t best = 0, chosen = 0;
};
Choice SmallestWithinTolerance(const std::vector<Candidate>& candidates,
                               const SelectionOptions& options);

/// Seconds of wall time since `start` (a candidate's TrainingCost).
inline double SecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

/// The largest score within the candidates' tolerance of `score`: 5 % or 0.005 NDEI above it.
double Tolerated(double score, const SelectionOptions& options);

/// Trains `c`'s setting on `fit` (epochs as given, the hold-out choosing among them when there
/// is one; scored by the context's criterion) and returns the model.
NarxModel TrainCandidate(const SelectionContext& ctx, const Candidate& c, const Series& fit,
                         const Series* holdout, int epochs, TrainReport* report = nullptr,
                         bool with_simulation = false);

/// Fills `c`'s rules and hold-out scores from `model`; its score is the criterion's NDEI
/// (infinite when not finite).
void ScoreCandidate(const SelectionContext& ctx, Candidate& c, const NarxModel& model);

/// The criterion's NDEI: free run (horizon 0), one step (1) or `horizon` steps ahead.
double Score(const NarxModel& model, const Series& s, int horizon);

/// Blocked cross-validation of the chosen fuzzy setting against the linear model: fold k is
/// scored after training on the rest of the context's `train`, the seam a break. `linear_folds`,
/// when given, are the linear model's fold scores from an earlier check. `second_look`: the
/// fuzzy candidate is not the hold-out's choice, so the folds alone must show that it beats the
/// linear model.
LinearCheck CrossValidate(const SelectionContext& ctx, const Candidate& fuzzy_c,
                          const Candidate& linear_c,
                          const std::vector<double>* linear_folds = nullptr,
                          bool second_look = false);

/// The short list (the linear model and the best fuzzy candidates by hold-out score) trained on
/// the simulation error, the restarts from the linear model's fit, and with free run reported the
/// linear model's output-error fit (kept when the folds prefer it).
void TrainShortListOnSimulation(const SelectionContext& ctx, SelectionState& st);

/// The chosen fuzzy candidate (then the next by hold-out score) against the linear model in
/// blocked cross-validation: the first that beats it is chosen, else the linear model.
void CheckAgainstLinear(const SelectionContext& ctx, SelectionState& st);

}  // namespace odonata::sysid

#pragma once
// The offline learner in one call (docs/identifier.md §9): the settings not given are chosen on
// a hold-out of the training series (SelectModel), then the chosen setting is trained on all of
// it (NarxModel::Train). odonata-fit runs it on a file; the online identifier's scheduled refits
// run it on the samples they keep (scheduled_refitter.hpp) — one learner, two schedules.

#include <functional>
#include <optional>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/search_subsample.hpp"

namespace odonata::sysid {

/// The final training's epochs and how long it is expected to take: the chosen candidate's
/// measured cost per epoch and per simulation step, times the final epochs and steps, times the
/// rows it trains on over the rows the candidate did (the hold-out's scoring, which the final
/// training does not do, is a few percent of a candidate's time). Zero seconds when unknown.
struct FinalTrainingEstimate {
  int epochs = 1;
  double epochs_seconds = 0.0;
  double simulation_seconds = 0.0;
};
FinalTrainingEstimate EstimateFinalTraining(const Candidate& chosen, Eigen::Index fit_rows,
                                            Eigen::Index final_rows, int final_epochs);

struct OfflineFitOptions {
  /// Choose the settings on a hold-out (SelectModel with `selection`); false trains `config` and
  /// `train` as they are.
  bool search = true;
  SelectionOptions selection;
  /// A long record's settings are chosen on blocks spread over it (search_subsample.hpp), then
  /// trained on all of it.
  SearchSubsample search_budget;
  /// The epoch count in `train` was given, not chosen: candidates train that many epochs.
  bool epochs_given = false;
  /// Declared scaling (the online identifier's ranges): every candidate and the final model use
  /// it. Empty: the scaling is fitted on the training series.
  std::optional<Scaling> scaling;
  /// Called with the final training's plan once it is known, before it starts (may be empty).
  std::function<void(const FinalTrainingEstimate&)> on_training;
};

struct OfflineFit {
  NarxModel model;
  fuzzy::FuzzyModelConfig config;  ///< the setting trained (chosen or given)
  TrainOptions train;              ///< epochs and simulation schedule trained with
  std::optional<SelectionResult> selection;
  /// Rows the search saw (the training series' and a selection series'): fewer than the record
  /// when it was subsampled; 0 without a search.
  Eigen::Index searched_rows = 0, searched_selection_rows = 0;
  TrainReport report;
};

/// Selection (when options.search), then training on all of `train`. `selection_series`, when
/// given, scores the candidates instead of a hold-out of `train`.
/// @throws std::invalid_argument when the series is too short for the lags.
OfflineFit FitOffline(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& config,
                      const TrainOptions& train, const Series& series,
                      const OfflineFitOptions& options, const CandidateProgress& on_candidate = {},
                      const Series* selection_series = nullptr);

}  // namespace odonata::sysid

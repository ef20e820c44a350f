#pragma once
// One scheduled refit, as the worker thread runs it (ScheduledRefitter starts it and lands what
// it gives; docs/identifier.md §6.3): odonata-fit's learner on the samples kept, then the checks
// that decide what lands — the last selection's setting reused at steady state, the incumbent
// kept, an expert's rules kept, a linear model trained beside the fuzzy one for the landing to
// judge it by. Everything a job reads is its own copy, so the samples keep arriving meanwhile.

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/estimation/consequent_tracker.hpp"
#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/model/sample.hpp"
#include "sysid/online/live_intervals.hpp"
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

/// What a refit does.
enum class RefitKind : std::uint8_t {
  /// odonata-fit's selection on the samples kept; a linear model trained beside the choice for
  /// the landing to judge it on the samples that come in meanwhile (LinearWinsTheNewSamples).
  kSelect,
  /// Steady state: train with the settings the last selection chose (one training instead of a
  /// search; a selection when there is none yet), judged at landing as kSelect is.
  kReuseSetting,
  /// The refit that closes learning: odonata-fit's defaults on the samples kept, its own scaling,
  /// no incumbent, no linear model beside it (no sample comes in while it runs).
  kClosing,
};

/// A selection's outcome, to train with again (RefitKind::kReuseSetting).
struct RefitSetting {
  fuzzy::FuzzyModelConfig config;
  TrainOptions train;
  std::size_t samples = 0;  ///< the samples it chose on
  /// What its checks held a model to: the criterion's horizon (0: free run), and with the
  /// free-run criterion the linear candidate's rest deviation (NaN: no rest check).
  int criterion_horizon = 0;
  double linear_rest = std::numeric_limits<double>::quiet_NaN();
  std::optional<Candidate> linear;  ///< its linear candidate (ARX), trained beside each refit
};

/// What a refit gives its landing.
struct RefitOutcome {
  RefitOutcome(NarxModel m, ConsequentTracker t) : model(std::move(m)), tracker(std::move(t)) {}
  NarxModel model;
  ConsequentTracker tracker;           ///< its prior: the refit's least-squares problem
  std::optional<RefitSetting> chosen;  ///< when this refit ran a selection
  bool incumbent_kept = false;         ///< the model it would replace stays (IncumbentHoldsItsOwn)
  bool steady_state_refused = false;   ///< the reused setting's model failed SteadyStateHolds
  /// The linear model (the selection's linear candidate) trained on the same samples, and the
  /// criterion both are scored by at landing, on the samples that came in meanwhile.
  std::optional<NarxModel> linear;
  ConsequentTracker linear_tracker;
  int criterion_horizon = 0;
  bool expert_kept = false;      ///< the expert's rules, refined, are this refit's model
  bool expert_replaced = false;  ///< this refit's choice beat the expert's rules
  /// When `model` is a selection's choice: its candidate's residuals on the selection's hold-out,
  /// the live intervals' start when it lands (LiveIntervals::Seed).
  std::optional<SeedResiduals> calibration;
};

/// Everything one refit reads.
struct RefitJob {
  RefitKind kind = RefitKind::kSelect;
  RegressorSpec spec;
  fuzzy::FuzzyModelConfig base;  ///< the settings the refits search around
  Series series;                 ///< the samples kept
  unsigned threads = 1;
  int horizon = 0;
  Scaling declared;                           ///< the identifier's declared envelope
  std::optional<RefitSetting> reuse;          ///< kReuseSetting: the last selection's
  std::optional<NarxModel> incumbent;         ///< the last refit's model as it landed
  int64_t unseen = 0;                         ///< samples kept since the incumbent's refit began
  std::optional<NarxModel> expert;            ///< rules an expert gave, until a refit beats them
  std::shared_ptr<std::atomic<bool>> cancel;  ///< raised: stop at the next training pass
};

/// Runs `job`. Never throws: a refit that cannot fit (or was cancelled) gives nullopt and says
/// why in `failure` ("cancelled", or its exception's message).
std::optional<RefitOutcome> RunRefit(const RefitJob& job, std::string& failure);

}  // namespace odonata::sysid

#include "sysid/online/refit_job.hpp"

#include <exception>
#include <stdexcept>
#include <utility>

#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/online/refit_judgements.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {
namespace {

// odonata-fit's defaults, with the regressors in the identifier's declared envelope and the
// outputs standardised on the samples kept, as odonata-fit standardises them. Regressors scaled
// to a partial buffer's own range spread the rules over what has been seen so far (a 200-sample
// refit grew many rules, 15× the cost); outputs scaled to the declared range changed the choice
// (vertical_wide: 2 rules at 87 % free run where odonata-fit on the same file chose 3 at 97 %).
// The closing refit is odonata-fit's defaults on the samples kept, scaling included: each
// candidate scaled to what it trains on, as odonata-fit scales a file. With the declared envelope
// instead, the closing refit on the tail-sitter's and the Flapper's whole training flights chose
// other models than odonata-fit on the same samples (the Flapper's v_z, 50 steps ahead on its
// selection flight: 6 rules at -6.8 % where odonata-fit's 2 rules give 27.8 %).
OfflineFitOptions RefitFitOptions(const RefitJob& job, const RegressionData& kept) {
  OfflineFitOptions o;
  Scaling scaling = Scaling::FromData(kept.x, kept.y);
  scaling.regressor_mid = job.declared.regressor_mid;
  scaling.regressor_half = job.declared.regressor_half;
  if (job.kind != RefitKind::kClosing) o.scaling = scaling;
  o.selection.simulation = DefaultSimulationStages();
  o.selection.threads = job.threads;
  o.selection.horizon = job.horizon;
  // The consequent kind is the configuration's (readable singletons stay singletons, and a
  // snapshot still fits the identifier that resumes it); H̄, κ and epochs are chosen.
  o.selection.consequents = {job.base.consequent};
  return o;
}

// The last refit's model stays, as it landed (it passed this refit's checks).
RefitOutcome KeepIncumbent(const RefitJob& job, const RegressionData& kept, bool refused_model) {
  RefitOutcome out(*job.incumbent, ConsequentTracker::Build(*job.incumbent, kept));
  out.incumbent_kept = true;
  out.steady_state_refused = refused_model;
  return out;
}

// The settings the last selection chose, trained on the samples kept now: odonata-fit
// --no-select with them (the search is most of a refit's cost). Trained with no hold-out, its
// model must pass the checks a selection's model passes: nullopt with `refused` when it does not
// (on the Silverbox, refits that reused a setting landed models that ran away in free run).
std::optional<OfflineFit> TrainWithTheLastSetting(const RefitJob& job, const OfflineFitOptions& o,
                                                  bool& refused) {
  OfflineFitOptions r = o;
  r.search = false;
  r.epochs_given = true;
  TrainOptions rt = job.reuse->train;
  rt.fit_scaling = false;
  rt.grow_rules = true;
  rt.progress = nullptr;
  rt.cancel = job.cancel.get();
  OfflineFit fit = FitOffline(job.spec, job.reuse->config, rt, job.series, r);
  refused = !SteadyStateHolds(fit.model, job.series, job.reuse->criterion_horizon,
                              job.reuse->linear_rest);
  if (refused) return std::nullopt;
  return fit;
}

// An expert's rules, refined on the samples kept: this refit's model unless its own choice beats
// them on the hold-out by the margin (ExpertHoldsItsOwn).
RefitOutcome ExpertRulesRefined(const RefitJob& job, const RegressionData& kept, bool refused) {
  NarxModel rules = RefineExpert(*job.expert, job.series);
  rules.FitEnvelope(job.series);
  ConsequentTracker tracker = ConsequentTracker::Build(rules, kept);
  RefitOutcome out(std::move(rules), std::move(tracker));
  out.steady_state_refused = refused;
  out.expert_kept = true;
  return out;
}

// The linear model on the same samples as the fuzzy one, for the landing to judge the fuzzy one
// against on the samples that come in meanwhile (LinearWinsTheNewSamples). ARX: one epoch of
// least squares, no simulation-error stages — the linear candidate's output-error fit judged the
// tail-sitter's replays no better (v_z 59.0 and 54.0 % live against 59.6 and 52.1 %) for one more
// such training per refit.
void TrainLinearBeside(const RefitJob& job, const OfflineFitOptions& o, const RefitSetting& setting,
                       const RegressionData& kept, RefitOutcome& out) {
  OfflineFitOptions lo = o;
  lo.search = false;
  lo.epochs_given = true;
  TrainOptions lt;
  lt.cancel = job.cancel.get();
  lt.epochs = 1;
  lt.simulation.clear();
  lt.deviation_ridge = 0.0;
  try {
    out.linear =
        FitOffline(job.spec, CandidateConfig(job.base, *setting.linear), lt, job.series, lo).model;
    out.linear_tracker = ConsequentTracker::Build(*out.linear, kept);
    out.criterion_horizon = setting.criterion_horizon;
  } catch (const std::exception&) {
    // Without it the fuzzy model lands unjudged rather than the refit being lost (if this was a
    // cancellation, the refit never lands anyway).
    out.linear.reset();
  }
}

// The chosen candidate's residuals on the hold-out it was judged on (the samples' end), per mode,
// as odonata-fit calibrates its intervals (fit/prediction_intervals.hpp); none without one.
std::optional<SeedResiduals> HoldoutResiduals(const RefitJob& job, const SelectionResult& sel) {
  if (!sel.chosen_model || sel.holdout_samples <= 0) return std::nullopt;
  const Series holdout = SplitAtHoldout(job.series, sel.holdout_samples).holdout;
  const NarxModel& candidate = *sel.chosen_model;
  const Predictor predict = [&candidate](const Eigen::VectorXd& x) { return candidate.Predict(x); };
  const Eigen::MatrixXd y = Targets(job.spec, holdout);
  auto modes = ModePredictions(job.spec, holdout, predict, job.horizon);
  SeedResiduals seed;
  seed.one_step = y - modes["one_step"];
  if (modes.count("free_run") > 0) seed.free_run = y - modes["free_run"];
  if (modes.count("k_step") > 0) {
    seed.ahead = y - modes["k_step"];
    seed.horizon = job.horizon;
  }
  return seed;
}

// The refit's steps in order; throws what FitOffline throws (TrainingCancelled included).
RefitOutcome Refit(const RefitJob& job) {
  const RegressionData kept = BuildRegression(job.spec, job.series);
  const OfflineFitOptions o = RefitFitOptions(job, kept);
  // 1. Steady state: the last setting, or the incumbent when that setting's model fails its
  //    checks and the incumbent passes them; otherwise a selection after all.
  std::optional<OfflineFit> reused;
  bool refused = false;
  if (job.reuse) {
    reused = TrainWithTheLastSetting(job, o, refused);
    if (refused && job.incumbent &&
        SteadyStateHolds(*job.incumbent, job.series, job.reuse->criterion_horizon,
                         job.reuse->linear_rest))
      return KeepIncumbent(job, kept, true);
  }
  // 2. Otherwise odonata-fit's learner: the selection (or, closing, its defaults).
  TrainOptions t;
  t.cancel = job.cancel.get();
  OfflineFit fit = reused ? std::move(*reused) : FitOffline(job.spec, job.base, t, job.series, o);
  std::optional<RefitSetting> chosen;
  if (fit.selection)
    chosen = RefitSetting{fit.config,
                          fit.train,
                          static_cast<std::size_t>(job.series.samples()),
                          fit.selection->criterion_horizon,
                          LinearRest(*fit.selection),
                          LinearBeside(*fit.selection)};
  // 3. An expert's rules stay, refined, unless this refit's own choice beats them.
  bool expert_replaced = false;
  if (job.expert && fit.selection) {
    if (ExpertHoldsItsOwn(*job.expert, *fit.selection, job.series, o.selection))
      return ExpertRulesRefined(job, kept, refused);
    expert_replaced = true;
  }
  // 4. The incumbent stays when it beats the choice on a hold-out it has not seen either.
  if (job.kind != RefitKind::kClosing && job.incumbent && fit.selection &&
      fit.selection->holdout_samples <= job.unseen &&
      IncumbentHoldsItsOwn(*job.incumbent, *fit.selection, job.series, o.selection))
    return KeepIncumbent(job, kept, refused);
  // 5. The choice lands, with the linear model beside it for the landing's judgement, and its
  //    candidate's hold-out residuals for the intervals.
  std::optional<SeedResiduals> calibration;
  if (fit.selection) {
    try {
      calibration = HoldoutResiduals(job, *fit.selection);
    } catch (const std::invalid_argument&) {
      // A hold-out with no complete regressor (breaks every few samples): the model still lands,
      // its intervals go on from the window they have.
    }
  }
  ConsequentTracker tracker = ConsequentTracker::Build(fit.model, kept);
  RefitOutcome out(std::move(fit.model), std::move(tracker));
  out.calibration = std::move(calibration);
  out.chosen = std::move(chosen);
  out.steady_state_refused = refused;
  out.expert_replaced = expert_replaced;
  const RefitSetting* setting = out.chosen ? &*out.chosen : (job.reuse ? &*job.reuse : nullptr);
  if (job.kind != RefitKind::kClosing && setting && setting->linear)
    TrainLinearBeside(job, o, *setting, kept, out);
  return out;
}

}  // namespace

std::optional<RefitOutcome> RunRefit(const RefitJob& job, std::string& failure) {
  try {
    return Refit(job);
  } catch (const std::exception& e) {  // the model keeps learning; the reason is reported
    failure = dynamic_cast<const TrainingCancelled*>(&e) ? "cancelled" : e.what();
    return std::nullopt;
  }
}

}  // namespace odonata::sysid

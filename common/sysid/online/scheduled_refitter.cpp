#include "sysid/online/scheduled_refitter.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <stdexcept>
#include <vector>

#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {

bool RefitSchedule::Due(int64_t learned) const {
  if (!enabled() || learned < first) return false;
  if (every > 0 && learned >= every) return learned % every == 0;
  // first, 2·first, 4·first, … (below `every`, when there is one)
  int64_t at = first;
  while (at < learned) at *= 2;
  return at == learned;
}

int64_t RefitSchedule::HistoryBlock() const {
  if (!(history > 0.0)) return 0;
  const auto block =
      static_cast<int64_t>(std::min(history, 1.0) * static_cast<double>(buffer)) / kHistoryBlocks;
  return block >= kShortestHistoryBlock ? block : 0;
}

namespace {

// The selection's linear candidate, if it had one.
std::optional<Candidate> LinearCandidate(const SelectionResult& selection) {
  const auto linear = std::find_if(selection.candidates.begin(), selection.candidates.end(),
                                   [](const Candidate& c) { return c.linear; });
  if (linear == selection.candidates.end()) return std::nullopt;
  return *linear;
}

// The rest deviation a model is held to: the free-run criterion's linear candidate's (NaN: none).
double LinearRest(const SelectionResult& selection) {
  const std::optional<Candidate> linear = LinearCandidate(selection);
  return selection.free_run_criterion && linear ? linear->rest_deviation
                                                : std::numeric_limits<double>::quiet_NaN();
}

// The linear candidate beside a fuzzy choice, to train with each refit; none when the choice is
// the linear model.
std::optional<Candidate> LinearBeside(const SelectionResult& selection) {
  if (selection.candidates[selection.chosen].linear) return std::nullopt;
  return LinearCandidate(selection);
}

// The samples in order, each copied once into the series.
Series SeriesFromSampleRefs(const std::vector<const Sample*>& samples) {
  Series s;
  if (samples.empty()) return s;
  const auto n = static_cast<Eigen::Index>(samples.size());
  s.outputs.resize(n, samples.front()->outputs.size());
  s.inputs.resize(n, samples.front()->inputs.size());
  for (Eigen::Index r = 0; r < n; ++r) {
    const Sample& x = *samples[static_cast<std::size_t>(r)];
    s.outputs.row(r) = x.outputs.transpose();
    s.inputs.row(r) = x.inputs.transpose();
    if (r > 0 && x.index != samples[static_cast<std::size_t>(r - 1)]->index + 1)
      s.breaks.push_back(r);
  }
  return s;
}

}  // namespace

Series SeriesFromSamples(const std::deque<Sample>& samples) {
  std::vector<const Sample*> refs;
  refs.reserve(samples.size());
  for (const Sample& x : samples) refs.push_back(&x);
  return SeriesFromSampleRefs(refs);
}

bool IncumbentHoldsItsOwn(const NarxModel& incumbent, const SelectionResult& selection,
                          const Series& series, const SelectionOptions& options) {
  // The hold-out is the newest samples, which the incumbent (it began before them) never saw, as
  // the chosen candidate did not (trained on the fit slice): the same test for both. A search
  // on blocks of a longer buffer has no such slice of it.
  if (selection.fit_samples + selection.holdout_samples != series.samples()) return false;
  const Series holdout = SliceSeries(series, selection.fit_samples, selection.holdout_samples);
  const double held = incumbent.NdeiAhead(holdout, selection.criterion_horizon);
  if (!(std::isfinite(held) &&
        BeatsByMargin(held, selection.candidates[selection.chosen].score, options)))
    return false;
  // A fuzzy incumbent must also beat the linear model there, by the same margin: the chosen
  // candidate faced the linear model in cross-validation, the incumbent never did.
  const std::optional<Candidate> linear = LinearCandidate(selection);
  if (incumbent.total_rules() > incumbent.outputs() && linear && std::isfinite(linear->score) &&
      !BeatsByMargin(held, linear->score, options))
    return false;
  // The checks a refit's own model passes: it runs on the whole buffer without diverging and,
  // with the free-run criterion, comes to rest where the linear model does.
  return SteadyStateHolds(incumbent, series, selection.criterion_horizon, LinearRest(selection));
}

NarxModel RefineExpert(const NarxModel& expert, const Series& series) {
  NarxModel refined = expert;
  const RegressionData d = BuildRegression(expert.spec(), series);
  const Eigen::MatrixXd xs = expert.scaling().ScaleRegressorRows(d.x);
  const Eigen::MatrixXd ys = expert.scaling().ScaleOutputRows(d.y);
  // The solve's own ridge (TrainOptions::ridge); a failed solve leaves that output as written.
  for (int o = 0; o < expert.outputs(); ++o)
    refined.mutable_model(o).RefineConsequents(xs, ys.col(o), TrainOptions{}.ridge);
  return refined;
}

bool ExpertHoldsItsOwn(const NarxModel& expert, const SelectionResult& selection,
                       const Series& series, const SelectionOptions& options) {
  if (selection.fit_samples + selection.holdout_samples != series.samples()) return true;
  const NarxModel refined = RefineExpert(expert, SliceSeries(series, 0, selection.fit_samples));
  const double held =
      refined.NdeiAhead(SliceSeries(series, selection.fit_samples, selection.holdout_samples),
                        selection.criterion_horizon);
  const double chosen = selection.candidates[selection.chosen].score;
  return !(std::isfinite(chosen) && BeatsByMargin(chosen, held, options));
}

bool LinearWinsTheNewSamples(const NarxModel& fuzzy, const NarxModel& linear, const Series& fresh,
                             int criterion_horizon) {
  // A few rows decide nothing.
  if (TargetRows(fuzzy.spec(), fresh).size() < 10) return false;
  // On the thread that takes the samples: K steps ahead, every target costs K predictions, so
  // only every (K/10)-th is scored. All 2 000 took 31 ms 50 steps ahead, where a landing takes
  // under 1 ms (bench_refit_realtime --horizon 50); the newest 400 alone judged the tail-sitter's
  // models wrongly both ways.
  const int stride = std::max(1, criterion_horizon / kLandingCheckStrideDivisor);
  const double l = linear.NdeiAhead(fresh, criterion_horizon, stride);
  // A linear model no better than the samples' own mean says only that neither model knows
  // them (the plant moved somewhere new); the fuzzy one, tracked, may still learn it fastest.
  if (!(l < 1.0)) return false;
  // NdeiAhead is +∞ for a model that runs away, which any finite score beats.
  return BeatsByMargin(l, fuzzy.NdeiAhead(fresh, criterion_horizon, stride), SelectionOptions{});
}

bool SteadyStateHolds(const NarxModel& model, const Series& series, int criterion_horizon,
                      double linear_rest) {
  if (!std::isfinite(model.NdeiAhead(series, criterion_horizon))) return false;
  return !(std::isfinite(linear_rest) && Restless(RestDeviation(model, series), linear_rest));
}

ScheduledRefitter::~ScheduledRefitter() { Clear(); }

void ScheduledRefitter::Keep(const Sample& s) {
  if (!schedule_.enabled()) return;
  recent_.push_back(s);
  const int64_t block = schedule_.HistoryBlock();
  const auto least = static_cast<std::size_t>(schedule_.RecentSamples());
  while (kept() > static_cast<std::size_t>(schedule_.buffer)) {
    if (block > 0 && recent_.size() <= least) {
      stride_ *= 2;
      archive_.erase(
          std::remove_if(archive_.begin(), archive_.end(),
                         [&](const Archived& a) { return (a.order / block) % stride_ != 0; }),
          archive_.end());
      continue;
    }
    // The oldest recent sample leaves the run: archived if its block is one the archive keeps.
    const int64_t order = order_++;
    if (block > 0 && (order / block) % stride_ == 0)
      archive_.push_back(Archived{order, std::move(recent_.front())});
    recent_.pop_front();
  }
}

Series ScheduledRefitter::KeptSeries() const {
  // Built where a refit starts, on the thread that takes the samples: each copied once.
  std::vector<const Sample*> kept;
  kept.reserve(archive_.size() + recent_.size());
  for (const Archived& a : archive_) kept.push_back(&a.sample);
  for (const Sample& x : recent_) kept.push_back(&x);
  return SeriesFromSampleRefs(kept);
}

void ScheduledRefitter::Start(const NarxModel& model, bool select, bool judged, bool closing) {
  pending_at_ = KeptSinceStart();
  if (!base_) base_ = model.model(0).config();
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  failure_ = std::make_shared<std::string>();
  std::optional<Chosen> reuse;
  if (!select) reuse = chosen_;
  // Everything the worker reads is its own copy (the cancel flag and the failure are shared).
  pending_ = std::async(
      std::launch::async,
      [spec = model.spec(), base = *base_, series = KeptSeries(), threads = schedule_.threads,
       horizon = schedule_.horizon, declared = model.scaling(), reuse = std::move(reuse),
       incumbent = landed_, unseen = pending_at_ - landed_at_, judged, closing, expert = expert_,
       cancel = cancel_, failure = failure_]() -> std::optional<Refitted> {
        try {
          OfflineFitOptions o;
          // odonata-fit's defaults, with the regressors in the identifier's declared envelope and
          // the outputs standardised on the samples kept, as odonata-fit standardises them.
          // Regressors scaled to a partial buffer's own range spread the rules over what has been
          // seen so far (a 200-sample refit grew many rules, 15× the cost); outputs scaled to the
          // declared range changed the choice (vertical_wide: 2 rules at 87 % free run where
          // odonata-fit on the same file chose 3 at 97 %).
          const RegressionData kept = BuildRegression(spec, series);
          Scaling scaling = Scaling::FromData(kept.x, kept.y);
          scaling.regressor_mid = declared.regressor_mid;
          scaling.regressor_half = declared.regressor_half;
          // The closing refit is odonata-fit's defaults on the samples kept, scaling included: each
          // candidate scaled to what it trains on, as odonata-fit scales a file. With the declared
          // envelope instead, the closing refit on the tail-sitter's and the Flapper's whole
          // training flights chose other models than odonata-fit on the same samples (the
          // Flapper's v_z, 50 steps ahead on its selection flight: 6 rules at -6.8 % where
          // odonata-fit's 2 rules give 27.8 %; docs/identifier.md §6.3).
          if (!closing) o.scaling = scaling;
          o.selection.simulation = DefaultSimulationStages();
          o.selection.threads = threads;
          o.selection.horizon = horizon;
          // The consequent kind is the configuration's (readable singletons stay singletons, and
          // a snapshot still fits the identifier that resumes it); H̄, κ and epochs are chosen.
          o.selection.consequents = {base.consequent};
          TrainOptions t;
          t.cancel = cancel.get();
          // The last refit's model stays, as it landed (it passed this refit's checks).
          const auto keep_incumbent = [&](bool refused_model) {
            return Refitted{*incumbent,          ConsequentTracker::Build(*incumbent, kept),
                            std::nullopt,        true,
                            refused_model,       std::nullopt,
                            ConsequentTracker{}, 0};
          };
          std::optional<OfflineFit> reused;
          bool refused = false;
          if (reuse) {
            // The settings the last selection chose, trained on the samples kept now: odonata-fit
            // --no-select with them. The search is most of a refit's cost.
            OfflineFitOptions r = o;
            r.search = false;
            r.epochs_given = true;
            TrainOptions rt = reuse->train;
            rt.fit_scaling = false;
            rt.grow_rules = true;
            rt.progress = nullptr;
            rt.cancel = cancel.get();
            reused = FitOffline(spec, reuse->config, rt, series, r);
            // Trained with no hold-out, it passes the checks a selection's model passes; if not,
            // the incumbent stays when it passes them on these samples, and otherwise the refit
            // selects after all. On the Silverbox, refits that reused a setting landed models
            // that ran away in free run (docs/identifier.md §6.3).
            refused = !SteadyStateHolds(reused->model, series, reuse->criterion_horizon,
                                        reuse->linear_rest);
            if (refused) {
              reused.reset();
              if (incumbent && SteadyStateHolds(*incumbent, series, reuse->criterion_horizon,
                                                reuse->linear_rest))
                return keep_incumbent(true);
            }
          }
          OfflineFit fit = reused ? std::move(*reused) : FitOffline(spec, base, t, series, o);
          std::optional<Chosen> chosen;
          if (fit.selection)
            chosen = Chosen{fit.config,
                            fit.train,
                            static_cast<std::size_t>(series.samples()),
                            fit.selection->criterion_horizon,
                            LinearRest(*fit.selection),
                            LinearBeside(*fit.selection)};
          // An expert's rules stay, refined, unless this refit's own choice beats them on the
          // hold-out by the margin (ExpertHoldsItsOwn).
          bool expert_replaced = false;
          if (expert && fit.selection) {
            if (ExpertHoldsItsOwn(*expert, *fit.selection, series, o.selection)) {
              NarxModel kept_rules = RefineExpert(*expert, series);
              kept_rules.FitEnvelope(series);
              ConsequentTracker rules_tracker = ConsequentTracker::Build(kept_rules, kept);
              Refitted out{std::move(kept_rules),
                           std::move(rules_tracker),
                           std::nullopt,
                           false,
                           refused,
                           std::nullopt,
                           ConsequentTracker{},
                           0};
              out.expert_kept = true;
              return out;
            }
            expert_replaced = true;
          }
          if (!closing && incumbent && fit.selection && fit.selection->holdout_samples <= unseen &&
              IncumbentHoldsItsOwn(*incumbent, *fit.selection, series, o.selection))
            return keep_incumbent(refused);
          ConsequentTracker tracker = ConsequentTracker::Build(fit.model, kept);
          Refitted out{std::move(fit.model),
                       std::move(tracker),
                       std::move(chosen),
                       false,
                       refused,
                       std::nullopt,
                       ConsequentTracker{},
                       0};
          out.expert_replaced = expert_replaced;
          // The linear model on the same samples, for the landing to judge the fuzzy one
          // against on the samples that come in meanwhile (LinearWinsTheNewSamples).
          const Chosen* setting = out.chosen ? &*out.chosen : (reuse ? &*reuse : nullptr);
          if (judged && setting && setting->linear) {
            OfflineFitOptions lo = o;
            lo.search = false;
            lo.epochs_given = true;
            // ARX: one epoch of least squares, no simulation-error stages. The linear
            // candidate's output-error fit judged the tail-sitter's replays no better (v_z 59.0
            // and 54.0 % live against 59.6 and 52.1 %) for one more such training per refit.
            TrainOptions lt = t;
            lt.epochs = 1;
            lt.simulation.clear();
            lt.deviation_ridge = 0.0;
            try {
              out.linear =
                  FitOffline(spec, CandidateConfig(base, *setting->linear), lt, series, lo).model;
              out.linear_tracker = ConsequentTracker::Build(*out.linear, kept);
              out.criterion_horizon = setting->criterion_horizon;
            } catch (const std::exception&) {
              // Without it the fuzzy model lands unjudged rather than the refit being lost (if
              // this was a cancellation, the refit never lands anyway).
              out.linear.reset();
            }
          }
          return out;
        } catch (const std::exception& e) {  // the model keeps learning; the reason is reported
          *failure = dynamic_cast<const TrainingCancelled*>(&e) ? "cancelled" : e.what();
          return std::nullopt;
        }
      });
}

bool ScheduledRefitter::Land(NarxModel& model) {
  if (!pending_.valid()) return false;
  if (wait_hook_ && pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready) {
    do {
      if (wait_hook_() == RefitWait::kGiveUp) {
        Cancel();
        ++failed_;
        last_failure_ = "given up while waiting for it (a stop, or the wait's bound)";
        return false;
      }
    } while (pending_.wait_for(wait_hook_period_) != std::future_status::ready);
  }
  std::optional<Refitted> refitted = pending_.get();
  if (!refitted) {
    ++failed_;
    if (failure_) last_failure_ = *failure_;
    return false;
  }
  ++refits_;
  ++landed_since_clear_;
  if (refitted->steady_state_refused) ++steady_state_refused_;
  if (refitted->expert_kept) ++experts_kept_;
  if (refitted->expert_replaced && expert_) {
    expert_.reset();  // a refit beat the expert's rules: later refits are free
    expert_replaced_ = true;
  }
  // The samples kept since the refit began; the judgement scores the newest of them (all in the
  // recent run), at most kLandingCheckSamples.
  const auto since = static_cast<std::size_t>(KeptSinceStart() - pending_at_);
  const auto fresh = std::min({since, recent_.size(), kLandingCheckSamples});
  bool arx_landed = false;
  if (refitted->linear && fresh > 0) {
    if (LinearWinsTheNewSamples(refitted->model, *refitted->linear, NewestRecent(fresh),
                                refitted->criterion_horizon)) {
      refitted->model = std::move(*refitted->linear);
      refitted->tracker = std::move(refitted->linear_tracker);
      ++linear_landed_;
      arx_landed = true;
    }
  }
  if (refitted->incumbent_kept) {
    // The last refit's model as it landed, which the check judged, not as tracking has moved
    // it since: it stays the incumbent, still unseen by the samples since it began.
    ++incumbents_kept_;
  } else {
    landed_ = refitted->model;
    landed_at_ = pending_at_;
  }
  model = std::move(refitted->model);
  tracker_ = std::move(refitted->tracker);
  // ARX is least squares on these rows, so learning the samples that came in meanwhile makes it
  // ARX on every sample the refit and they hold. A fuzzy refit's consequents are trained on
  // simulation error instead, and the same rows pull them toward the one-step fit: on the
  // tail-sitter's q (select → train flight) 0.5 s ahead that fell from 36.1 to -48.4 %, and the
  // Silverbox's live models lost 0.4 to 0.8 FIT points in 7 of 8 replays (docs/identifier.md §6.3).
  if (arx_landed) CatchUp(model, since);
  if (refitted->chosen) {
    chosen_ = std::move(refitted->chosen);
    ++selections_;
  }
  return true;
}

Series ScheduledRefitter::NewestRecent(std::size_t count) const {
  std::vector<const Sample*> refs;
  refs.reserve(count);
  for (auto it = recent_.end() - static_cast<std::ptrdiff_t>(count); it != recent_.end(); ++it)
    refs.push_back(&*it);
  return SeriesFromSampleRefs(refs);
}

void ScheduledRefitter::CatchUp(NarxModel& model, std::size_t since) {
  const std::size_t newest = std::min(since, recent_.size());
  if (tracker_.empty() || newest == 0) return;
  // The lags before the first of them, where the recent run has them.
  const std::size_t lead =
      std::min(recent_.size() - newest, static_cast<std::size_t>(model.spec().first_target()));
  RegressionData rows;
  try {
    rows = BuildRegression(model.spec(), NewestRecent(newest + lead));
  } catch (const std::invalid_argument&) {
    return;  // too few, or gaps in every stretch: no complete regressor to learn from
  }
  for (Eigen::Index k = 0; k < rows.x.rows(); ++k)
    tracker_.Step(model, rows.x.row(k).transpose(), rows.y.row(k).transpose());
}

bool ScheduledRefitter::AfterLearn(NarxModel& model, int64_t learned) {
  if (!schedule_.enabled()) return false;
  if (!base_) base_ = model.model(0).config();
  learned_ = learned;
  if (schedule_base_ < 0) schedule_base_ = learned - 1;
  const int64_t since_clear = learned - schedule_base_;  // 1 at the first sample learned
  if (!schedule_.Due(since_clear)) return false;
  const bool landed = Land(model);
  // A refit chooses its settings until one has chosen on a full buffer; from then on, at steady
  // state (every `every` samples), it trains with what that selection chose: a later search
  // would see no more samples. A buffer spread over the run is short of full just after its
  // stride doubles (with the defaults at 6000 samples), and a selection on it does not count:
  // counted, the Silverbox's replays ended on the linear model twice in six (docs/identifier.md
  // §6.3). Counts decide, so a replay makes the same choices.
  const bool informed = chosen_ && chosen_->samples >= static_cast<std::size_t>(schedule_.buffer);
  // While an expert's rules stand, every refit selects: a steady-state refit has no hold-out to
  // judge them on.
  Start(model, expert_.has_value() ||
                   !(informed && schedule_.every > 0 && since_clear >= schedule_.every));
  last_started_ = learned;
  return landed;
}

void ScheduledRefitter::BeginClosing(const NarxModel& model) {
  if (!schedule_.enabled()) return;
  if (schedule_.at_freeze && learned_ > last_started_ && kept() > 0) {
    // The closing refit learns from every sample kept, from the refits' own settings: whatever
    // the refit in flight would have given, it replaces.
    Cancel();
    // The closing refit is odonata-fit's defaults on every sample kept: its selection, its
    // cross-validation against the linear model, its scaling. No sample comes in while it runs,
    // so no linear model is trained beside it to judge it on them, and the incumbent does not
    // compete: a model judged on one hold-out slice, never cross-validated against the linear
    // model, would bypass the guard odonata-fit's own choice passes (docs/identifier.md §6.3).
    Start(model, true, false, true);
    last_started_ = learned_;
  }
  closing_ = pending_.valid();
}

bool ScheduledRefitter::Settle(NarxModel& model) {
  if (!closing_) return false;
  closing_ = false;
  return Land(model);
}

void ScheduledRefitter::Cancel() {
  if (cancel_) cancel_->store(true);
  if (pending_.valid()) pending_.wait();
  pending_ = {};
  cancel_.reset();
}

void ScheduledRefitter::Clear() {
  Cancel();
  tracker_ = ConsequentTracker{};
  chosen_.reset();
  landed_.reset();
  expert_.reset();
  experts_kept_ = 0;
  expert_replaced_ = false;
  landed_at_ = pending_at_ = 0;
  closing_ = false;
  recent_.clear();
  archive_.clear();
  order_ = 0;
  stride_ = 1;
  base_.reset();
  last_started_ = -1;
  learned_ = 0;
  schedule_base_ = -1;
  landed_since_clear_ = 0;
}

}  // namespace odonata::sysid

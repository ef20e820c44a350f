#include "sysid/scheduled_refitter.hpp"

#include <exception>

#include "sysid/offline_fit.hpp"
#include "sysid/simulation_error_training.hpp"

namespace odonata::sysid {

bool RefitSchedule::Due(int64_t learned) const {
  if (!enabled() || learned < first) return false;
  if (every > 0 && learned >= every) return learned % every == 0;
  // first, 2·first, 4·first, … (below `every`, when there is one)
  int64_t at = first;
  while (at < learned) at *= 2;
  return at == learned;
}

Series SeriesFromSamples(const std::deque<Sample>& samples) {
  Series s;
  if (samples.empty()) return s;
  const auto n = static_cast<Eigen::Index>(samples.size());
  s.outputs.resize(n, samples.front().outputs.size());
  s.inputs.resize(n, samples.front().inputs.size());
  for (Eigen::Index r = 0; r < n; ++r) {
    const Sample& x = samples[static_cast<std::size_t>(r)];
    s.outputs.row(r) = x.outputs.transpose();
    s.inputs.row(r) = x.inputs.transpose();
    if (r > 0 && x.index != samples[static_cast<std::size_t>(r - 1)].index + 1)
      s.breaks.push_back(r);
  }
  return s;
}

ScheduledRefitter::~ScheduledRefitter() { Clear(); }

void ScheduledRefitter::Keep(const Sample& s) {
  if (!schedule_.enabled()) return;
  kept_.push_back(s);
  while (kept_.size() > static_cast<std::size_t>(schedule_.buffer)) kept_.pop_front();
}

Series ScheduledRefitter::KeptSeries() const { return SeriesFromSamples(kept_); }

void ScheduledRefitter::Start(const NarxModel& model, bool select) {
  if (!base_) base_ = model.model(0).config();
  cancel_ = std::make_shared<std::atomic<bool>>(false);
  std::optional<Chosen> reuse;
  if (!select) reuse = chosen_;
  // Everything the worker reads is its own copy (the cancel flag is shared, atomic).
  pending_ = std::async(
      std::launch::async,
      [spec = model.spec(), base = *base_, series = KeptSeries(), threads = schedule_.threads,
       declared = model.scaling(), reuse = std::move(reuse),
       cancel = cancel_]() -> std::optional<Refitted> {
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
          o.scaling = scaling;
          o.selection.simulation = DefaultSimulationStages();
          o.selection.threads = threads;
          // The consequent kind is the configuration's (readable singletons stay singletons, and
          // a snapshot still fits the identifier that resumes it); H̄, κ and epochs are chosen.
          o.selection.consequents = {base.consequent};
          TrainOptions t;
          fuzzy::FuzzyModelConfig cfg = base;
          if (reuse) {
            // The settings the last selection chose, trained on the samples kept now: odonata-fit
            // --no-select with them. The search is most of a refit's cost.
            o.search = false;
            o.epochs_given = true;
            cfg = reuse->config;
            t = reuse->train;
            t.fit_scaling = false;
            t.grow_rules = true;
            t.progress = nullptr;
          }
          t.cancel = cancel.get();
          OfflineFit fit = FitOffline(spec, cfg, t, series, o);
          std::optional<Chosen> chosen;
          if (fit.selection)
            chosen = Chosen{fit.config, fit.train, static_cast<std::size_t>(series.samples())};
          ConsequentTracker tracker = ConsequentTracker::Build(fit.model, kept);
          return Refitted{std::move(fit.model), std::move(tracker), std::move(chosen)};
        } catch (const std::exception&) {
          // Too few samples for the hold-out and the lags, or cancelled: keep the model learning.
          return std::nullopt;
        }
      });
}

bool ScheduledRefitter::Land(NarxModel& model) {
  if (!pending_.valid()) return false;
  if (wait_hook_ && pending_.wait_for(std::chrono::seconds(0)) != std::future_status::ready)
    wait_hook_();
  std::optional<Refitted> refitted = pending_.get();
  if (!refitted) {
    ++failed_;
    return false;
  }
  model = std::move(refitted->model);
  tracker_ = std::move(refitted->tracker);
  if (refitted->chosen) {
    chosen_ = std::move(refitted->chosen);
    ++selections_;
  }
  ++refits_;
  return true;
}

bool ScheduledRefitter::AfterLearn(NarxModel& model, int64_t learned) {
  if (!schedule_.enabled()) return false;
  if (!base_) base_ = model.model(0).config();
  learned_ = learned;
  if (!schedule_.Due(learned)) return false;
  const bool landed = Land(model);
  // A refit chooses its settings until one has chosen on a full buffer; from then on, at steady
  // state (every `every` samples), it trains with what that selection chose: a later search
  // would see no more samples. Counts decide, so a replay makes the same choices.
  const bool informed = chosen_ && chosen_->samples >= static_cast<std::size_t>(schedule_.buffer);
  Start(model, !(informed && schedule_.every > 0 && learned >= schedule_.every));
  last_started_ = learned;
  return landed;
}

void ScheduledRefitter::BeginClosing(const NarxModel& model) {
  if (!schedule_.enabled()) return;
  if (schedule_.at_freeze && learned_ > last_started_ && !kept_.empty()) {
    // The closing refit learns from every sample kept, from the refits' own settings: whatever
    // the refit in flight would have given, it replaces.
    Cancel();
    Start(model, true);  // the closing refit is odonata-fit's defaults on every sample kept
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
  closing_ = false;
  kept_.clear();
  base_.reset();
  last_started_ = -1;
  learned_ = 0;
}

}  // namespace odonata::sysid

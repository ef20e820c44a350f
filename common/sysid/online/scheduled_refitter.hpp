#pragma once
// One learner, two schedules (docs/identifier.md §6.3). The online identifier learns sample by
// sample and, at fixed counts of samples learned, refits its model with odonata-fit's own
// learner (FitOffline: selection, least squares, premise epochs, simulation-error training) on
// the samples it keeps. A refit runs in a worker thread while samples keep arriving, and lands
// at the next scheduled count. Until the first refit lands, the per-sample learner grows and
// tunes the model; from then on the refits own it: the per-sample learner's independent per-rule
// RLS and premise steps pull a jointly fitted model apart (Narendra's plant: a refit at 99.5 %
// one step fell to 79 % after 500 samples of them), so between refits the model holds and the
// samples are only kept. Starting and landing at fixed counts, never at a time,
// makes a lockstep run and odonata-fit's replay of the same samples (LearnOnline) give the same
// model bit for bit, however long a refit takes.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/estimation/consequent_tracker.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/model/sample.hpp"
#include "sysid/online/refit_job.hpp"
#include "sysid/online/refit_schedule.hpp"
#include "sysid/online/sample_archive.hpp"

namespace odonata::sysid {

/// What a landing that waits for its refit does next (ScheduledRefitter::SetWaitHook).
enum class RefitWait { kKeepWaiting, kGiveUp };

/// Keeps the samples learned (SampleArchive) and runs the refits of a schedule on them (RefitJob
/// in a worker thread), landing each at the next scheduled count.
class ScheduledRefitter {
 public:
  explicit ScheduledRefitter(RefitSchedule schedule) : schedule_(schedule), samples_(schedule) {}
  ScheduledRefitter(const ScheduledRefitter&) = delete;
  ScheduledRefitter& operator=(const ScheduledRefitter&) = delete;
  ~ScheduledRefitter();

  /// A sample the model is learning from (regressor complete or not): kept for the refits.
  void Keep(const Sample& s);
  /// After sample number `learned` was learned (or, once a refit has landed, kept): when a refit
  /// is due, the one in flight lands in `model` and the next one starts.
  /// @return true when a refit landed.
  bool AfterLearn(NarxModel& model, int64_t learned);
  /// Learning stops. With schedule.at_freeze and samples learned since the last refit began, a
  /// closing refit on the samples kept begins (it supersedes the one in flight, which is
  /// cancelled); otherwise the refit in flight is the closing one. It does not wait: Settle()
  /// lands it, before the model is next used.
  void BeginClosing(const NarxModel& model);
  /// Lands the closing refit, if one is in flight (waits for it). @return true when it landed.
  bool Settle(NarxModel& model);
  /// Between refits: one step of recursive global least squares on the consequents of the model
  /// the last refit gave (ConsequentTracker), for the raw regressor x and measured y.
  void Track(NarxModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
    tracker_.Step(model, x, y);
  }
  /// Rows the landed model's tracker has learned: those caught up at its landing (CatchUp), then
  /// one per sample tracked.
  long tracked() const { return tracker_.steps(); }
  /// Called before a landing waits for a refit that has not finished (not when it has), and
  /// again every `period` while it still waits: the identifier says, and keeps saying, that it
  /// is busy, so a lockstep generator waits instead of resending, and one that starts meanwhile
  /// still hears it (docs/lcm.md §10).
  /// The hook answers whether to go on waiting: kGiveUp (a stop was asked for, or the wait is
  /// past its bound) cancels the refit (it stops at its next training pass), counts it as failed
  /// with the reason, and the model keeps learning as it was.
  void SetWaitHook(std::function<RefitWait()> hook,
                   std::chrono::milliseconds period = std::chrono::milliseconds(1000)) {
    wait_hook_ = std::move(hook);
    wait_hook_period_ = period;
  }
  /// Forgets everything (a model from elsewhere replaced this one); a refit in flight is
  /// cancelled (it stops at its next training pass or step) and dropped. The destructor too.
  void Clear();
  /// Rules an expert wrote (the .fis or model file the identifier started from): every refit
  /// selects, and its own choice replaces them only when it beats them — their consequents
  /// refined by least squares on the same fit slice, their premises as written — on the
  /// hold-out by the margin a candidate needs over a simpler one (ExpertHoldsItsOwn). Otherwise
  /// the refit lands the expert's rules with their consequents refined on every sample kept.
  /// Once replaced, they are gone (later refits are free).
  void SetExpert(NarxModel expert) { expert_ = std::move(expert); }
  bool has_expert() const { return expert_.has_value(); }
  /// Refits that landed the expert's rules, refined; and whether a refit replaced them.
  int64_t experts_kept() const { return experts_kept_; }
  bool expert_replaced() const { return expert_replaced_; }

  const RefitSchedule& schedule() const { return schedule_; }
  std::size_t kept() const { return samples_.size(); }
  /// Archived blocks are the multiples of this (SampleArchive::stride).
  int64_t history_stride() const { return samples_.stride(); }
  /// The samples a refit would learn from now, oldest first (a break at every skipped index).
  Series KeptSeries() const { return samples_.All(); }
  int64_t refits() const { return refits_; }  ///< refits landed
  /// Whether a refit has landed since the last Clear (a RESET, a restore, a resume): from then on
  /// the refits own the model and per-sample learning stops; before, the model learns per sample.
  bool owns_model() const { return landed_since_clear_ > 0; }
  int64_t failed() const { return failed_; }  ///< refits that could not fit
  /// Why the last refit that failed did (its exception's message, "cancelled", or empty).
  const std::string& last_failure() const { return last_failure_; }
  /// The last landed model's calibration residuals (RefitOutcome::calibration), once: empty when
  /// it was not a selection's own choice (ARX, the incumbent, an expert's rules) or was taken.
  std::optional<SeedResiduals> TakeLandedCalibration() { return std::exchange(calibration_, {}); }
  /// Refits landed that chose their settings (a model selection); the others trained with the
  /// settings the last selection chose (see Start).
  int64_t selections() const { return selections_; }
  /// Refits that kept the model they would have replaced (IncumbentHoldsItsOwn).
  int64_t incumbents_kept() const { return incumbents_kept_; }
  /// Steady-state refits whose model failed its checks (SteadyStateHolds): the incumbent stayed
  /// or the refit selected instead.
  int64_t steady_state_refused() const { return steady_state_refused_; }
  /// Refits that landed the linear model trained beside them instead of their fuzzy one, which
  /// lost to it on the samples that came in while they ran (LinearWinsTheNewSamples).
  int64_t linear_landed() const { return linear_landed_; }
  /// The most samples that judgement scores on (the newest): 20 s at 100 Hz.
  static constexpr std::size_t kLandingCheckSamples = 2000;
  bool in_flight() const { return pending_.valid(); }
  bool closing() const { return closing_; }

 private:
  /// Starts a refit of `kind` on the samples kept, in a worker thread.
  void Start(const NarxModel& model, RefitKind kind);
  void Cancel();
  bool Land(NarxModel& model);
  /// The landed model's tracker learns the newest `since` samples kept (those that came in while
  /// its refit ran), one row each, as Track would have, as far as the recent run still holds
  /// them: all of them until the buffer first fills; at steady state (a refit every `buffer`
  /// samples) the newest 3 000–4 000 of 6 000 with the defaults, the archive's older blocks not.
  /// Land calls it for an ARX landed by the judgement only (why: there).
  void CatchUp(NarxModel& model, std::size_t since);

  RefitSchedule schedule_;
  std::optional<fuzzy::FuzzyModelConfig> base_;  ///< the settings the refits search around
  SampleArchive samples_;
  std::optional<NarxModel> landed_;  ///< the last refit's model as it landed
  std::optional<NarxModel> expert_;  ///< rules an expert gave, until a refit beats them
  int64_t experts_kept_ = 0;
  bool expert_replaced_ = false;
  /// Samples kept since the start (or Clear) when the refit in flight, and the one that landed
  /// last, began: the samples since the latter are ones its model never saw.
  int64_t pending_at_ = 0, landed_at_ = 0;
  std::optional<RefitSetting> chosen_;        // the last selection's settings
  std::optional<SeedResiduals> calibration_;  // the last landing's, until taken
  std::future<std::optional<RefitOutcome>> pending_;
  ConsequentTracker tracker_;  // the landed refit's
  /// Raised to stop the refit in flight when it will never land (Clear, the destructor).
  std::shared_ptr<std::atomic<bool>> cancel_;
  int64_t learned_ = 0;  ///< the count AfterLearn last saw
  /// The count before the first AfterLearn since Clear: the schedule counts from there, so that a
  /// restart at sample N (a restore, a resume) refits at N + first, inside the run, not at the
  /// schedule's next point past N (with the defaults 12 000 for a restore at 4 400).
  int64_t schedule_base_ = -1;
  std::shared_ptr<std::string> failure_;  ///< the worker's reason, read after it ends
  std::string last_failure_;
  int64_t landed_since_clear_ = 0;
  int64_t last_started_ = -1;  ///< the count the last refit began at
  bool closing_ = false;       ///< the refit in flight lands at Settle()
  int64_t refits_ = 0;
  int64_t failed_ = 0;
  int64_t selections_ = 0;
  int64_t incumbents_kept_ = 0;
  int64_t steady_state_refused_ = 0;
  int64_t linear_landed_ = 0;
  std::function<RefitWait()> wait_hook_;
  std::chrono::milliseconds wait_hook_period_{1000};
};

}  // namespace odonata::sysid

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
#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

/// When the online learner refits (counts of samples learned, 1-based).
struct RefitSchedule {
  int64_t first = 0;  ///< the first refit starts after this many samples; 0: never refit
  int64_t every = 0;  ///< then at 2×, 4×, … first below this, then at every multiple of it
  /// The identifier's default: 10 s, 20 s, 40 s, then every 60 s at 100 Hz (docs/identifier.md
  /// §6.3; a struct left as it is never refits, as odonata-fit's own default).
  static RefitSchedule IdentifierDefault() {
    RefitSchedule s;
    s.first = 1000;
    s.every = 6000;
    return s;
  }
  /// The samples kept for a refit: 2 min at 100 Hz, so the closing refit of a flight of a minute
  /// or two sees all of it, as odonata-fit would. With 6 000, the closing refits of 70 s flights
  /// (tail-sitter, Flapper; training files) saw 5 500 of their 7 000 samples and chose models
  /// far from odonata-fit's on the same flight (docs/identifier.md §6.3).
  int64_t buffer = 12000;
  /// The share of `buffer` that may hold blocks spread over everything learned before the most
  /// recent samples (docs/identifier.md §6.3): a long record's refit still sees its whole range of
  /// operation, not the last minute only. 0: the most recent `buffer` samples.
  double history = 0.5;
  /// Blocks are history·buffer / kHistoryBlocks samples: three to six of them are kept.
  static constexpr int64_t kHistoryBlocks = 6;
  /// Shorter blocks would be mostly lags and windows cut short: the archive is off below this.
  static constexpr int64_t kShortestHistoryBlock = 100;
  /// Samples in one archived block; 0 when the archive is off.
  int64_t HistoryBlock() const;
  /// The fewest most recent samples the buffer keeps whole.
  int64_t RecentSamples() const { return buffer - kHistoryBlocks * HistoryBlock(); }
  /// When learning stops (a freeze, the end of a replayed file), the refit in flight lands and
  /// one more refit on the samples kept closes learning.
  bool at_freeze = true;
  /// Threads a refit trains its candidates on (SelectionOptions::threads): one leaves the other
  /// cores to the services beside it; the model is the same whatever the count.
  unsigned threads = 1;
  /// K > 1: a refit's selection scores and chooses K steps ahead (SelectionOptions::horizon, as
  /// odonata-fit --horizon) — for a loop that integrates, whose free run drifts for any model;
  /// 0: free run, as odonata-fit's default (docs/identifier.md §6.3).
  int horizon = 0;
  bool enabled() const { return first > 0 && buffer > 0; }
  /// True when a refit starts after sample number `learned`.
  bool Due(int64_t learned) const;
};

/// What a landing that waits for its refit does next (ScheduledRefitter::SetWaitHook).
enum class RefitWait { kKeepWaiting, kGiveUp };

/// Keeps the samples learned and runs the refits of a schedule on them. Once `buffer` samples
/// have been learned the buffer is full, or short by up to three blocks just after a doubling
/// (below): a run of the most recent samples, at least RecentSamples() long, and before it an
/// archive of whole blocks spread over everything older.
/// Block b (samples b·L … b·L + L − 1 in the order learned) is archived when b is a multiple of
/// the stride; a sample leaving the recent run is archived or dropped by its block, and when the
/// recent run would fall below RecentSamples() the stride doubles, dropping every other archived
/// block. The archive so stays spread evenly over the whole run, from its first sample, whatever
/// the run's length, at a fixed cost; which samples are kept depends on counts only.
class ScheduledRefitter {
 public:
  explicit ScheduledRefitter(RefitSchedule schedule) : schedule_(schedule) {}
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
  std::size_t kept() const { return recent_.size() + archive_.size(); }
  /// Archived blocks are the multiples of this (1 until the recent run first reaches its least).
  int64_t history_stride() const { return stride_; }
  /// The samples a refit would learn from now, oldest first (a break at every skipped index).
  Series KeptSeries() const;
  int64_t refits() const { return refits_; }  ///< refits landed
  /// Whether a refit has landed since the last Clear (a RESET, a restore, a resume): from then on
  /// the refits own the model and per-sample learning stops; before, the model learns per sample.
  bool owns_model() const { return landed_since_clear_ > 0; }
  int64_t failed() const { return failed_; }  ///< refits that could not fit
  /// Why the last refit that failed did (its exception's message, "cancelled", or empty).
  const std::string& last_failure() const { return last_failure_; }
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
  /// `select`: run odonata-fit's selection on the samples kept; otherwise train with the settings
  /// the last selection chose (when there is one), which costs one training instead of a search.
  /// `judged`: train the linear model beside a fuzzy one for the landing to judge it on the
  /// samples that come in meanwhile (LinearWinsTheNewSamples); a closing refit gets none.
  /// `closing`: the refit that closes learning, odonata-fit's defaults on the samples kept (its
  /// own scaling, no incumbent).
  void Start(const NarxModel& model, bool select, bool judged = true, bool closing = false);
  void Cancel();
  bool Land(NarxModel& model);
  /// The landed model's tracker learns the newest `since` samples kept (those that came in while
  /// its refit ran), one row each, as Track would have, as far as the recent run still holds
  /// them: all of them until the buffer first fills; at steady state (a refit every `buffer`
  /// samples) the newest 3 000–4 000 of 6 000 with the defaults, the archive's older blocks not.
  /// Land calls it for an ARX landed by the judgement only (why: there).
  void CatchUp(NarxModel& model, std::size_t since);
  /// The newest `count` samples of the recent run (at most its size), oldest first.
  Series NewestRecent(std::size_t count) const;

  RefitSchedule schedule_;
  std::optional<fuzzy::FuzzyModelConfig> base_;  ///< the settings the refits search around
  std::deque<Sample> recent_;                    ///< oldest first
  struct Archived {
    int64_t order = 0;  // the sample's place among those kept since the start (or Clear)
    Sample sample;
  };
  std::deque<Archived> archive_;  ///< oldest first, all older than recent_
  int64_t order_ = 0;  ///< samples that have left the recent run: the order of its oldest
  int64_t stride_ = 1;
  struct Chosen {  // a selection's outcome, to train with again
    fuzzy::FuzzyModelConfig config;
    TrainOptions train;
    std::size_t samples = 0;  // the samples it chose on
    // What its checks held a model to: the criterion's horizon (0: free run), and with the
    // free-run criterion the linear candidate's rest deviation (NaN: no rest check).
    int criterion_horizon = 0;
    double linear_rest = std::numeric_limits<double>::quiet_NaN();
    std::optional<Candidate> linear;  // its linear candidate (ARX), trained beside each refit
  };
  struct Refitted {
    NarxModel model;
    ConsequentTracker tracker;          // its prior: the refit's least-squares problem
    std::optional<Chosen> chosen;       // when this refit ran a selection
    bool incumbent_kept = false;        // the model it would replace stays (IncumbentHoldsItsOwn)
    bool steady_state_refused = false;  // the reused setting's model failed SteadyStateHolds
    // The linear model (the selection's linear candidate) trained on the same samples, and the
    // criterion both are scored by at landing, on the samples that came in meanwhile.
    std::optional<NarxModel> linear;
    ConsequentTracker linear_tracker;
    int criterion_horizon = 0;
    bool expert_kept = false;      // the expert's rules, refined, are this refit's model
    bool expert_replaced = false;  // this refit's choice beat the expert's rules
  };
  std::optional<NarxModel> landed_;  ///< the last refit's model as it landed
  std::optional<NarxModel> expert_;  ///< rules an expert gave, until a refit beats them
  int64_t experts_kept_ = 0;
  bool expert_replaced_ = false;
  /// Samples kept since the start (or Clear) when the refit in flight, and the one that landed
  /// last, began: the samples since the latter are ones its model never saw.
  int64_t pending_at_ = 0, landed_at_ = 0;
  int64_t KeptSinceStart() const { return order_ + static_cast<int64_t>(recent_.size()); }
  std::optional<Chosen> chosen_;  // the last selection's settings
  std::future<std::optional<Refitted>> pending_;
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

/// A selecting refit keeps the model the last refit landed (the incumbent) when, on the refit's
/// hold-out slice — its newest samples, unseen by both — the incumbent beats the candidate the
/// selection chose by the margin a candidate needs over a simpler one (docs/identifier.md §6.3):
/// a selection on one buffer can fall back to the linear model because its fuzzy candidates ran
/// away on one cross-validation fold, while the model learned from earlier buffers still
/// predicts the newest samples three times better.
bool IncumbentHoldsItsOwn(const NarxModel& incumbent, const SelectionResult& selection,
                          const Series& series, const SelectionOptions& options);

/// A refit that trained with the last selection's setting (steady state: no search, so no
/// hold-out) lands only when its model passes, on the samples kept, the checks that selection
/// held its model to (docs/identifier.md §6.3): a finite score by its criterion
/// (`criterion_horizon`, 0 free run) and, with `linear_rest` finite (the free-run criterion's
/// linear candidate), at rest where the linear model is. The incumbent is held to the same.
bool SteadyStateHolds(const NarxModel& model, const Series& series, int criterion_horizon,
                      double linear_rest);

/// `expert`'s rules with every consequent refitted by least squares on `series` (premises as
/// they are; the expert's scaling): the expert's local models refined on the vehicle's samples.
NarxModel RefineExpert(const NarxModel& expert, const Series& series);

/// The refit's own choice replaces an expert's rules only when it beats them — refined on the
/// selection's fit slice — on its hold-out by the margin a candidate needs over a simpler one
/// (false: they stay). A search on blocks of a longer buffer has no such slice: they stay.
bool ExpertHoldsItsOwn(const NarxModel& expert, const SelectionResult& selection,
                       const Series& series, const SelectionOptions& options);

/// At a landing, the samples that came in while the refit ran are ones neither the refit's
/// fuzzy model nor the linear model trained beside it (on the same samples) has seen: the linear
/// model lands instead when, on them, it beats the fuzzy one by the margin a candidate needs over
/// a simpler one, by the refit's criterion (`criterion_horizon`, 0 free run; docs/identifier.md
/// §6.3). A fuzzy model that runs away there loses to a linear one that does not.
bool LinearWinsTheNewSamples(const NarxModel& fuzzy, const NarxModel& linear, const Series& fresh,
                             int criterion_horizon);
/// K steps ahead, that judgement scores every (K / this)-th target only.
inline constexpr int kLandingCheckStrideDivisor = 10;

/// The series a refit learns from: the samples in order, a break wherever an index is skipped.
Series SeriesFromSamples(const std::deque<Sample>& samples);

}  // namespace odonata::sysid

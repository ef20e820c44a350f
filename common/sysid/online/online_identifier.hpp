#pragma once
// The online identifier's core: consumes samples one by one, in order, exactly as the offline
// trainer walks a CSV, so a lockstep run reproduces odonata-fit's model bit for bit. Knows
// nothing of LCM; the service shell turns messages into samples.

#include <chrono>
#include <cstdint>
#include <deque>
#include <functional>
#include <optional>

#include <Eigen/Core>

#include "sysid/estimation/recursive_arx.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/online/live_intervals.hpp"
#include "sysid/online/scheduled_refitter.hpp"
#include "sysid/online/settling_watch.hpp"

namespace odonata::sysid {

/// What the identifier says about sample k.
struct SampleReport {
  int64_t index = 0;
  Eigen::VectorXd measured;   ///< y(k)
  Eigen::VectorXd predicted;  ///< ŷ(k | k−1), before learning from y(k)
  Eigen::VectorXd free_run;   ///< the parallel model's own simulation of y(k)
  Eigen::VectorXd next;       ///< ŷ(k+1 | k) after learning (NaN when delay = 0: u(k+1) unknown)
  Eigen::VectorXi rules;
  Eigen::VectorXd max_entropy;
  bool learned = false;
  /// The live linear baseline on the same regressors (RecursiveArx): ŷ(k | k−1) and its own
  /// free run, so a consumer sees whether the fuzzy model beats linear.
  Eigen::VectorXd arx_predicted, arx_free_run;
  /// With a horizon K ≥ 2 (OnlineIdentifier::set_ahead_horizon), ŷ(k | k−K): the model's own
  /// simulation over the last K samples from the measured outputs before them (or from its
  /// segment's start), as odonata-fit's PredictAhead scores it; and the live ARX's, likewise.
  /// Empty without a horizon.
  Eigen::VectorXd ahead, arx_ahead;
  int horizon = 0;  ///< K of `ahead`
  /// Per output, the share of the model's global linear model in `predicted`: 0 when the
  /// regressor lies within the data the model was trained on, up to 1 beyond it (DataEnvelope).
  Eigen::VectorXd linear_share;
  /// Per output, the half width h of the interval ŷ ± h around `predicted` and around `ahead`
  /// (LiveIntervals, at `interval_level`): from the model's residuals on earlier samples it
  /// learned; +∞ while it has too few. `ahead_half_width` is empty without a horizon.
  Eigen::VectorXd half_width, ahead_half_width;
  /// Per output, the half width around `free_run`, from the free run's residuals likewise.
  Eigen::VectorXd free_run_half_width;
  double interval_level = 0.0;
  /// Per output, has the model seen enough at this sample (SettlingWatch::States; the same
  /// judgement as Settling()'s, without its sentences).
  std::vector<SettlingState> seen_enough;
};

/// kBridged: a short gap before the sample was filled by interpolation (OnlineIdentifier::
/// set_max_gap); kGap: a longer one restarted the history.
enum class PushResult { kAccepted, kBridged, kGap, kDuplicate, kRejected };

class OnlineIdentifier {
 public:
  /// `refit`: when to refit the model on the samples kept (ScheduledRefitter); none by default.
  explicit OnlineIdentifier(NarxModel model, RefitSchedule refit = {});

  /// Feeds sample k. A sample that does not follow the previous one after at most max_gap()
  /// missing ones bridges them: they are learned as the straight line between their neighbours,
  /// as odonata-fit bridges missing rows (docs/identifier.md §7.1), and get no report of their
  /// own. A longer gap restarts the history — regressors are never built across it. Earlier or
  /// repeated samples and non-finite values are rejected without touching the model.
  /// @return the report once the history holds a full regressor.
  std::optional<SampleReport> Push(const Sample& sample, PushResult* result = nullptr);

  /// Stops learning. With scheduled refits a closing refit begins (ScheduledRefitter::
  /// BeginClosing) without waiting; the model takes it at the next sample or Settle(), which
  /// wait for it. Until then model() is the model in force before the freeze.
  void Freeze();
  /// Lands a closing refit now (waits for it): before a model is saved or published.
  void Settle() { SettleRefit(); }
  void Resume() {
    SettleRefit();
    learning_ = true;
  }
  bool learning() const { return learning_; }
  /// Whether the model has seen enough, per output (SettlingWatch): settled, still learning or
  /// short of excitation, with the rules and regimes that say why. Judged on the samples learned.
  std::vector<OutputSettling> Settling() const { return settling_.Judge(model_); }
  /// Forgets the history (e.g. the plant was reset: a new run); the model is kept.
  void RestartHistory();
  /// Replaces the model (a saved model or a snapshot from the bus); the history restarts and
  /// the learned-sample count becomes `samples_learned` (a resumed model's own count).
  /// `learned_through` ≥ 0 is the newest sample index the model had learned (a snapshot's): until
  /// the run restarts (RestartHistory), samples at or before it are refused as already learned
  /// (kDuplicate; a replay of the run's earlier traffic teaches nothing twice), and the first
  /// later one counts those between as gaps (lost while the identifier was down).
  void ReplaceModel(NarxModel model, int64_t samples_learned = 0, int64_t learned_through = -1);
  /// The model it started from is an expert's (a .fis or model file): scheduled refits refine
  /// its rules and replace them only when their own choice beats them on the hold-out by the
  /// selection's margin (ScheduledRefitter::SetExpert). A replaced model (ReplaceModel) forgets it.
  void KeepExpertRules() {
    if (refitter_.schedule().enabled() && model_.total_rules() > 0) refitter_.SetExpert(model_);
  }
  /// Refits that landed the expert's rules (refined), and whether one replaced them.
  int64_t experts_kept() const { return refitter_.experts_kept(); }
  bool expert_replaced() const { return refitter_.expert_replaced(); }
  bool has_expert() const { return refitter_.has_expert(); }
  /// Called before the model waits for a scheduled refit that has not finished, and every
  /// `period` while it waits (ScheduledRefitter::SetWaitHook).
  void SetRefitWaitHook(std::function<RefitWait()> hook,
                        std::chrono::milliseconds period = std::chrono::milliseconds(1000)) {
    refitter_.SetWaitHook(std::move(hook), period);
  }
  /// @throws std::invalid_argument (model unchanged) outside the fuzzy core's range.
  void SetEntropyThreshold(double h);
  /// RLS forgetting factor λ of every output. @throws std::invalid_argument outside (0, 1].
  void SetForgetting(double lambda);

  const NarxModel& model() const { return model_; }
  /// The samples it keeps for its refits (ScheduledRefitter::KeptSeries): with none scheduled,
  /// none. What a saved model's parameter covariance is estimated on.
  Series KeptSeries() const { return refitter_.KeptSeries(); }
  /// The live ARX baseline: learns while the identifier learns, freezes with it, and starts
  /// again from nothing when the model is replaced (it is not part of a snapshot).
  const RecursiveArx& arx() const { return arx_; }
  int64_t samples_learned() const { return samples_learned_; }
  /// Samples missing before a later one arrived (bridged or not).
  int64_t gaps() const { return gaps_; }
  /// Of those, the samples bridged by interpolation (learned from, not reported).
  int64_t bridged() const { return bridged_; }
  /// Samples predicted (a report given), and of those the ones whose regressor lay outside the
  /// data the model was trained on (a linear share above 0 for some output; DataEnvelope).
  int64_t samples_predicted() const { return predicted_; }
  int64_t samples_outside() const { return outside_; }
  /// The longest run of missing samples bridged (0, the default: none, every gap restarts the
  /// history, as odonata-fit's replay of a series with breaks expects).
  int max_gap() const { return max_gap_; }
  /// @pre max_gap >= 0.
  void set_max_gap(int max_gap) { max_gap_ = max_gap; }
  /// K ≥ 2: every report carries ŷ(k | k−K) of the model and of the live ARX (SampleReport::
  /// ahead), for loops that integrate, where one step ahead says little; 0: none. Costs K model
  /// evaluations per sample. @throws std::invalid_argument for 1 or a negative K.
  void set_ahead_horizon(int horizon);
  int ahead_horizon() const { return ahead_horizon_; }
  /// Scheduled refits landed so far (ScheduledRefitter), and refits that found too few samples.
  int64_t refits() const { return refitter_.refits(); }
  int64_t failed_refits() const { return refitter_.failed(); }
  /// Why the last failed refit failed, as its exception said it.
  const std::string& last_refit_failure() const { return refitter_.last_failure(); }
  /// "(N failed)", with the last one's reason when there is one: as the identifier reports them.
  std::string FailedRefitsText() const;
  /// Of the refits landed, those that ran a model selection (ScheduledRefitter::selections).
  int64_t selections() const { return refitter_.selections(); }
  /// Of the refits landed, those that kept the last refit's model (IncumbentHoldsItsOwn).
  int64_t incumbents_kept() const { return refitter_.incumbents_kept(); }
  int64_t steady_state_refused() const { return refitter_.steady_state_refused(); }
  /// Of the refits landed, those that landed the linear model trained beside them
  /// (ScheduledRefitter::linear_landed).
  int64_t linear_landed() const { return refitter_.linear_landed(); }
  /// Rows the landed model's tracker has learned since it landed (ScheduledRefitter::tracked).
  long tracked() const { return refitter_.tracked(); }
  int64_t last_index() const { return last_index_; }
  /// The newest sample index the model has learned in this run (−1: none): a snapshot's
  /// `learned_through`, so a resumed identifier knows what it holds.
  int64_t learned_through() const { return have_last_ ? last_index_ : resume_after_; }
  /// Samples refused because the resumed model had learned them already (ReplaceModel).
  int64_t already_learned() const { return already_learned_; }
  /// Of gaps(), the samples between a resumed model's learned_through and the first later
  /// sample: lost while the identifier was down (or learned after its snapshot, lost with it).
  int64_t missed_on_resume() const { return missed_on_resume_; }

 private:
  /// Learns and predicts `s`, the sample after the history's newest.
  std::optional<SampleReport> Step(const Sample& s);
  /// Lands a closing refit if one is in flight; the settling watch judges its rules anew.
  void SettleRefit();
  /// A refit landed: the settling watch judges its rules anew and the intervals start from its
  /// calibration residuals (when it brought any).
  void Landed();

  NarxModel model_;
  bool learning_ = true;
  std::deque<Sample> history_;  // consecutive samples, newest last: first_target() + max(K, 1)
  std::deque<Eigen::VectorXd> free_history_;  // free-run outputs aligned with history_
  RecursiveArx arx_;
  std::deque<Eigen::VectorXd> arx_free_history_;  // the ARX's own free run, likewise
  int64_t last_index_ = -1;
  bool have_last_ = false;
  int64_t resume_after_ = -1;  // a resumed model's learned_through, until the first later sample
  int64_t already_learned_ = 0;
  int64_t missed_on_resume_ = 0;
  int64_t samples_learned_ = 0;
  int64_t gaps_ = 0;
  int64_t bridged_ = 0;
  int64_t predicted_ = 0;
  int64_t outside_ = 0;
  int max_gap_ = 0;
  int ahead_horizon_ = 0;
  ScheduledRefitter refitter_;
  SettlingWatch settling_;
  LiveIntervals intervals_;
};

/// odonata-fit's replay of the online identifier (docs/identifier.md §6.3): every row of `series`
/// pushed in order through an OnlineIdentifier with this schedule (a break skips an index), then
/// frozen, which closes learning as a freeze does. The model's scaling is fitted on the series
/// unless `scaling` is given (the identifier's declared ranges).
struct OnlineReplay {
  NarxModel model;
  int64_t refits = 0;
  int64_t failed_refits = 0;
  int64_t samples_learned = 0;
  int64_t incumbents_kept = 0;       ///< refits that kept the last refit's model
  int64_t steady_state_refused = 0;  ///< steady-state refits whose model failed its checks
  int64_t linear_landed = 0;  ///< refits whose fuzzy model lost to the linear one on new samples
  /// Whether the model had seen enough at the end (OnlineIdentifier::Settling), per output.
  std::vector<OutputSettling> settling;
};
/// `frozen` false replays an identifier stopped without a freeze: no closing refit, and the
/// refit in flight never lands.
OnlineReplay LearnOnline(NarxModel model, const RefitSchedule& refit, const Series& series,
                         const std::optional<Scaling>& scaling, bool frozen = true);

}  // namespace odonata::sysid

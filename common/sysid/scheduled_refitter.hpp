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
#include <cstdint>
#include <deque>
#include <functional>
#include <future>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "fuzzy/fuzzy_model.hpp"
#include "sysid/consequent_tracker.hpp"
#include "sysid/narx_model.hpp"

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
  int64_t buffer = 6000;  ///< the most recent samples kept for a refit (60 s at 100 Hz)
  /// When learning stops (a freeze, the end of a replayed file), the refit in flight lands and
  /// one more refit on the samples kept closes learning.
  bool at_freeze = true;
  /// Threads a refit trains its candidates on (SelectionOptions::threads): one leaves the other
  /// cores to the services beside it; the model is the same whatever the count.
  unsigned threads = 1;
  bool enabled() const { return first > 0 && buffer > 0; }
  /// True when a refit starts after sample number `learned`.
  bool Due(int64_t learned) const;
};

/// One sample as the online identifier receives it (raw units).
struct Sample {
  int64_t index = 0;  ///< k
  Eigen::VectorXd outputs;
  Eigen::VectorXd inputs;
};

/// Keeps the samples learned and runs the refits of a schedule on them.
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
  long tracked() const { return tracker_.steps(); }
  /// Called before a landing waits for a refit that has not finished (not when it has): the
  /// identifier says it is busy, so a lockstep generator waits instead of resending.
  void SetWaitHook(std::function<void()> hook) { wait_hook_ = std::move(hook); }
  /// Forgets everything (a model from elsewhere replaced this one); a refit in flight is
  /// cancelled (it stops at its next training pass or step) and dropped. The destructor too.
  void Clear();

  const RefitSchedule& schedule() const { return schedule_; }
  std::size_t kept() const { return kept_.size(); }
  int64_t refits() const { return refits_; }  ///< refits landed
  int64_t failed() const { return failed_; }  ///< refits that could not fit (too few samples)
  /// Refits landed that chose their settings (a model selection); the others trained with the
  /// settings the last selection chose (see Start).
  int64_t selections() const { return selections_; }
  bool in_flight() const { return pending_.valid(); }
  bool closing() const { return closing_; }

 private:
  Series KeptSeries() const;
  /// `select`: run odonata-fit's selection on the samples kept; otherwise train with the settings
  /// the last selection chose (when there is one), which costs one training instead of a search.
  void Start(const NarxModel& model, bool select);
  void Cancel();
  bool Land(NarxModel& model);

  RefitSchedule schedule_;
  std::optional<fuzzy::FuzzyModelConfig> base_;  ///< the settings the refits search around
  std::deque<Sample> kept_;                      ///< oldest first
  struct Chosen {                                // a selection's outcome, to train with again
    fuzzy::FuzzyModelConfig config;
    TrainOptions train;
    std::size_t samples = 0;  // the samples it chose on
  };
  struct Refitted {
    NarxModel model;
    ConsequentTracker tracker;     // its prior: the refit's least-squares problem
    std::optional<Chosen> chosen;  // when this refit ran a selection
  };
  std::optional<Chosen> chosen_;  // the last selection's settings
  std::future<std::optional<Refitted>> pending_;
  ConsequentTracker tracker_;  // the landed refit's
  /// Raised to stop the refit in flight when it will never land (Clear, the destructor).
  std::shared_ptr<std::atomic<bool>> cancel_;
  int64_t learned_ = 0;        ///< the count AfterLearn last saw
  int64_t last_started_ = -1;  ///< the count the last refit began at
  bool closing_ = false;       ///< the refit in flight lands at Settle()
  int64_t refits_ = 0;
  int64_t failed_ = 0;
  int64_t selections_ = 0;
  std::function<void()> wait_hook_;
};

/// The series a refit learns from: the samples in order, a break wherever an index is skipped.
Series SeriesFromSamples(const std::deque<Sample>& samples);

}  // namespace odonata::sysid

#pragma once
// odonata-monitor's scoring without transport: the identifier's predictions, run by run, scored
// over the whole run and a sliding window, one step ahead and in free run, with the change alarm
// (metrics/accuracy_alarm.hpp) and the low-FIT warning. Add() returns what the operator should
// be told, so the shell only prints and publishes, like pipeline::LockstepSequencer's actions.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "metrics/accuracy_alarm.hpp"
#include "metrics/conformal.hpp"
#include "metrics/running_accuracy.hpp"
#include "sequence/sequence_window.hpp"

namespace odonata::monitoring {

/// One prediction_t, as plain arrays (one entry per output).
struct Prediction {
  int64_t sample = 0;
  std::vector<std::string> names;
  std::vector<double> measured, predicted, free_run;
  std::vector<int> rules;
  /// The identifier's live ARX baseline (prediction_t.arx_*): empty when not carried (a
  /// prediction from an older writer), or one entry per output.
  std::vector<double> arx_predicted, arx_free_run;
  /// With a horizon K ≥ 2 (prediction_t.horizon): ŷ(k | k−K) of the model and of the live ARX,
  /// one entry per output; 0 and empty without.
  int horizon = 0;
  std::vector<double> ahead, arx_ahead;
  /// Per output, the share of the global linear model in `predicted` (prediction_t.linear_share):
  /// above 0, the sample lay outside the model's data. Empty when not carried.
  std::vector<double> linear_share;
  /// The identifier's intervals ŷ ± half width at `interval_level` (prediction_t): one entry per
  /// output (and per output with a horizon for `ahead_half_width`), −1 where not known yet;
  /// empty when not carried.
  double interval_level = 0.0;
  std::vector<double> half_width = {}, ahead_half_width = {}, free_run_half_width = {};
  /// Per output, has the model seen enough (prediction_t.seen_enough: 0 short of excitation, 1
  /// still learning, 2 settled); empty when not carried.
  std::vector<int> seen_enough = {};
};

struct ScoreboardOptions {
  std::size_t window_samples = 500;  ///< sliding window (5 s at 100 Hz)
  double warn_fit_percent = 80.0;    ///< warn when the window's one-step FIT drops below
  std::size_t alarm_window_samples = 100;
  double alarm_drop_points = 5.0;
  /// Behind the live ARX once the window's fuzzy FIT is not above the ARX's (K steps ahead when
  /// the predictions carry a horizon, else one step ahead); ahead again
  /// only when it leads by more than this many points, so a model that is as good as linear (one
  /// rule is a linear model) is said once, not at every sample the two swap places.
  double arx_margin_points = 0.5;
};

/// What a prediction changed that the operator should hear of.
struct ScoreEvent {
  enum class Kind {
    kNewRun,         ///< the sample number went back: a new run (`sample`, after `previous`)
    kAlarm,          ///< `output`'s tracking FIT fell (`fit` against a settled `reference`)
    kRecovered,      ///< back to `fit` against the `reference` before the alarm
    kLowFit,         ///< the window's one-step FIT `fit` fell below the warning level
    kLowFitCleared,  ///< back to `fit`
    kBehindArx,      ///< over a full window the fuzzy FIT `fit` is not above the live ARX's
                     ///< `reference` (`horizon` steps ahead, 1: one step): the rules are not
                     ///< paying for themselves
    kAheadOfArx      ///< the fuzzy model leads ARX again by more than arx_margin_points
  };
  Kind kind = Kind::kNewRun;
  std::string output;
  int64_t sample = 0;
  int64_t previous = 0;  ///< kNewRun: the last sample of the run that ended
  double fit = 0, reference = 0;
  int horizon = 1;  ///< kBehindArx, kAheadOfArx: the mode compared
};

/// One mode's score (one step ahead, K steps ahead or free run) over the run and the window.
struct ModeScore {
  metrics::CumulativeAccuracy total;
  metrics::WindowAccuracy window;
  explicit ModeScore(std::size_t window_samples) : window(window_samples) {}
  void Add(double measured, double predicted) {
    total.Add(measured, predicted);
    window.Add(measured, predicted);
  }
  bool scored() const { return total.samples() > 0; }
};

/// One predictor's scores (the fuzzy model's, or the live ARX's over the same samples) in each
/// mode: the one set of accumulators the scoreboard keeps per predictor.
struct PredictorScores {
  ModeScore one_step, free_run, ahead;
  explicit PredictorScores(std::size_t window_samples)
      : one_step(window_samples), free_run(window_samples), ahead(window_samples) {}
  /// The same keys for every predictor, so a reader compares like with like; `horizon`: K of
  /// the K-step scores, reported when there are any.
  nlohmann::json ToJson(int horizon) const;
};

class PredictionScoreboard {
 public:
  static constexpr std::size_t kMaxFinishedRuns = 16;  ///< earlier runs kept in the summary
  static constexpr std::size_t kMaxAlarmEvents = 64;   ///< alarm events kept per output and run
  /// Outputs scored per run: a model has at most RegressorSpec::kMaxSignals signals, so a
  /// prediction naming more (300 forged ones of 1000 names each once held 1.2 GB) is refused.
  static constexpr std::size_t kMaxOutputs = 256;

  /// One output's scores in the current run: the fuzzy model's and, over the same samples, the
  /// live ARX's (none counted when predictions carry none).
  struct Output {
    PredictorScores fuzzy, arx;
    int horizon = 0;      ///< K of `ahead` (0: predictions carry none)
    int64_t outside = 0;  ///< samples whose regressor lay outside the model's data
    bool behind_arx = false;
    metrics::AccuracyAlarm alarm;
    std::vector<nlohmann::json> alarm_events;  // the latest kMaxAlarmEvents
    int rules = 0;
    bool warned = false;
    double interval_level = 0.0;  ///< of the intervals tallied (0: none carried)
    metrics::IntervalTally one_step_interval, ahead_interval, free_run_interval;
    int seen_enough = -1;  ///< the last prediction's (prediction_t.seen_enough), −1: none carried
    Output(std::size_t w, const metrics::AccuracyAlarmOptions& a) : fuzzy(w), arx(w), alarm(a) {}
    bool has_arx() const { return arx.one_step.scored(); }
    bool has_ahead() const { return fuzzy.ahead.scored(); }
  };

  explicit PredictionScoreboard(ScoreboardOptions options) : options_(options) {}

  /// Scores `p`. A bad prediction (arrays of different lengths, NaN or Inf, a duplicate sample,
  /// a far leap) throws std::invalid_argument and changes nothing, so the genuine prediction for
  /// that sample still counts.
  std::vector<ScoreEvent> Add(const Prediction& p);

  /// Forgets the current run's scores (an operator's reset); earlier runs stay in the summary.
  void Reset();

  /// Outputs in first-seen order, and their scores.
  const std::vector<std::string>& outputs() const { return order_; }
  const Output& output(const std::string& name) const { return outputs_.at(name); }
  int64_t last_sample() const { return last_sample_; }
  int64_t gaps() const { return gaps_; }  ///< samples missing within the current run
  bool Warned(const std::string& output) const;
  bool Alarmed(const std::string& output) const;
  /// Over the last full window the fuzzy model's FIT was not above the live ARX's (K steps ahead
  /// with a horizon, else one step ahead).
  bool BehindArx(const std::string& output) const;

  /// The current run: last_sample, gaps and per output rules, one_step, free_run,
  /// window_one_step, window_free_run, with a horizon `horizon`, ahead and window_ahead,
  /// alarm_events, alarmed, and, when predictions carry the live ARX, "arx" (the same scores)
  /// and behind_arx.
  nlohmann::json RunSummary() const;
  /// RunSummary() with "previous_runs" (the latest kMaxFinishedRuns) when there were any.
  nlohmann::json Summary() const;

 private:
  ScoreboardOptions options_;
  std::vector<std::string> order_;
  std::map<std::string, Output> outputs_;
  int64_t last_sample_ = -1;
  pipeline::LeapGuard leaps_;  // a forged far-ahead sample must not split the run
  int64_t gaps_ = 0;
  std::vector<nlohmann::json> finished_runs_;  // summaries of runs before a plant restart
};

}  // namespace odonata::monitoring

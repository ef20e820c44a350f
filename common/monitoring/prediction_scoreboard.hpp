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
#include "metrics/running_accuracy.hpp"
#include "sequence/sequence_window.hpp"

namespace odonata::monitoring {

/// One prediction_t, as plain arrays (one entry per output).
struct Prediction {
  int64_t sample = 0;
  std::vector<std::string> names;
  std::vector<double> measured, predicted, free_run;
  std::vector<int> rules;
};

struct ScoreboardOptions {
  std::size_t window_samples = 500;  ///< sliding window (5 s at 100 Hz)
  double warn_fit_percent = 80.0;    ///< warn when the window's one-step FIT drops below
  std::size_t alarm_window_samples = 100;
  double alarm_drop_points = 5.0;
};

/// What a prediction changed that the operator should hear of.
struct ScoreEvent {
  enum class Kind {
    kNewRun,        ///< the sample number went back: a new run (`sample`, after `previous`)
    kAlarm,         ///< `output`'s tracking FIT fell (`fit` against a settled `reference`)
    kRecovered,     ///< back to `fit` against the `reference` before the alarm
    kLowFit,        ///< the window's one-step FIT `fit` fell below the warning level
    kLowFitCleared  ///< back to `fit`
  };
  Kind kind = Kind::kNewRun;
  std::string output;
  int64_t sample = 0;
  int64_t previous = 0;  ///< kNewRun: the last sample of the run that ended
  double fit = 0, reference = 0;
};

class PredictionScoreboard {
 public:
  static constexpr std::size_t kMaxFinishedRuns = 16;  ///< earlier runs kept in the summary
  static constexpr std::size_t kMaxAlarmEvents = 64;   ///< alarm events kept per output and run
  /// Outputs scored per run: a model has at most RegressorSpec::kMaxSignals signals, so a
  /// prediction naming more (300 forged ones of 1000 names each once held 1.2 GB) is refused.
  static constexpr std::size_t kMaxOutputs = 256;

  /// One output's scores in the current run.
  struct Output {
    metrics::CumulativeAccuracy total_one_step, total_free_run;
    metrics::WindowAccuracy window_one_step, window_free_run;
    metrics::AccuracyAlarm alarm;
    std::vector<nlohmann::json> alarm_events;  // the latest kMaxAlarmEvents
    int rules = 0;
    bool warned = false;
    Output(std::size_t w, const metrics::AccuracyAlarmOptions& a)
        : window_one_step(w), window_free_run(w), alarm(a) {}
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

  /// The current run: last_sample, gaps and per output rules, one_step, free_run,
  /// window_one_step, alarm_events, alarmed.
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

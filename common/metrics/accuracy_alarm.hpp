#pragma once
// A change detector on live accuracy: raises an alarm when the sliding-window FIT falls well
// below the level the model had settled at, and says when it is back (docs/identifier.md §5.1).

#include <optional>

#include "metrics/tracking_accuracy.hpp"

namespace odonata::metrics {

struct AccuracyAlarmOptions {
  std::size_t window = 100;  ///< samples in the sliding window (1 s at 100 Hz)
  /// Samples over which the output's spread is measured (TrackingAccuracy); 0: 10 windows.
  std::size_t span = 0;
  double drop_points = 5.0;     ///< alarm when window FIT < reference − drop_points
  double recover_points = 1.0;  ///< recovered when window FIT ≥ pre-alarm reference − this
  /// Time constant of the reference (settled) level, samples; 0: three windows.
  double reference_samples = 0.0;
};

/// What changed at a sample.
struct AccuracyEvent {
  enum class Kind { kAlarm, kRecovered };
  Kind kind = Kind::kAlarm;
  long sample = 0;
  double window_fit = 0.0;     ///< tracking FIT % at the event (TrackingAccuracy)
  double reference_fit = 0.0;  ///< the settled level it is compared with
};

/// Fed (measured, predicted) sample by sample, in order. It watches the tracking FIT (the
/// window's error against the span's spread, TrackingAccuracy). The reference is an exponential
/// average of it while no alarm is raised, frozen while one is; so a slow drift moves the
/// reference, a sudden loss raises the alarm, and recovery means back near the level before it.
class AccuracyAlarm {
 public:
  explicit AccuracyAlarm(const AccuracyAlarmOptions& options = {});

  std::optional<AccuracyEvent> Push(long sample, double measured, double predicted);

  bool alarmed() const { return alarmed_; }
  double window_fit() const { return window_fit_; }
  /// The tracking FIT now (NaN until the span is full): what the alarm watches, sample by sample.
  double tracking_fit() const { return window_.fit_percent(); }
  double reference_fit() const { return reference_; }

 private:
  AccuracyAlarmOptions options_;
  TrackingAccuracy window_;
  bool alarmed_ = false;
  bool have_reference_ = false;
  double reference_ = 0.0;
  double window_fit_ = 0.0;
  long settled_ = 0;  // samples since the window filled (or since recovery)
};

}  // namespace odonata::metrics

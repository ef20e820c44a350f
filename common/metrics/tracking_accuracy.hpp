#pragma once
// Live accuracy for change detection: the error over a short window, measured against the
// output's spread over a longer span (docs/identifier.md §5.1).

#include <cstddef>
#include <deque>

namespace odonata::metrics {

/// FIT_track = 100 (1 − RMSE over the last `window` samples / std of the measured output over
/// the last `span` samples). A window FIT normalised by the window's own spread (WindowAccuracy)
/// swings by tens of points whenever the vehicle holds a level for a second, though the model is
/// as good as ever; the span's spread is the scale of the excitation, so this one moves only when
/// the error does. Over a whole stationary run it approaches the run's one-step FIT.
class TrackingAccuracy {
 public:
  /// @pre 2 ≤ window ≤ span.
  TrackingAccuracy(std::size_t window, std::size_t span);
  /// Non-finite samples are ignored.
  void Add(double measured, double predicted);
  /// Ready once the span is full.
  bool ready() const { return y_.size() == span_; }
  /// FIT_track in %; NaN until ready or while the span's output is constant.
  double fit_percent() const;
  std::size_t window() const { return window_; }

 private:
  void Resum();

  std::size_t window_, span_;
  std::deque<double> y_;   // measured, last `span`
  std::deque<double> e2_;  // squared error, last `window`
  double sum_y_ = 0.0, sum_y2_ = 0.0, sum_e2_ = 0.0;
  std::size_t since_resum_ = 0;
};

}  // namespace odonata::metrics

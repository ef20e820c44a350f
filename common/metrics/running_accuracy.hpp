#pragma once
// Accuracy accumulated sample by sample: since start (constant memory) and over a sliding
// window (the last N samples), for a live monitor.

#include <cstddef>
#include <deque>

#include "metrics/accuracy.hpp"

namespace odonata::metrics {

/// FIT, VAF, RMSE since start from running sums (Welford, so long runs do not lose precision).
class CumulativeAccuracy {
 public:
  void Add(double measured, double predicted);
  Accuracy Get() const;
  void Reset() { *this = CumulativeAccuracy(); }
  long samples() const { return n_; }

 private:
  long n_ = 0;
  double mean_y_ = 0, m2_y_ = 0;  // Welford on y
  double mean_e_ = 0, m2_e_ = 0;  // Welford on e = y − ŷ
  double sum_e2_ = 0;
};

/// The same measures over the last `window` samples.
class WindowAccuracy {
 public:
  explicit WindowAccuracy(std::size_t window) : window_(window) {}
  void Add(double measured, double predicted);
  Accuracy Get() const;
  std::size_t size() const { return y_.size(); }
  bool full() const { return y_.size() == window_; }
  void Reset() { y_.clear(), yhat_.clear(); }

 private:
  std::size_t window_;
  std::deque<double> y_, yhat_;
};

}  // namespace odonata::metrics

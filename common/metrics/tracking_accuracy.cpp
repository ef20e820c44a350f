#include "metrics/tracking_accuracy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "contract/precondition.hpp"

namespace odonata::metrics {

TrackingAccuracy::TrackingAccuracy(std::size_t window, std::size_t span)
    : window_(window), span_(span) {
  ODONATA_EXPECTS(window >= 2 && window <= span);
}

void TrackingAccuracy::Add(double measured, double predicted) {
  if (!std::isfinite(measured) || !std::isfinite(predicted)) return;
  const double e2 = (measured - predicted) * (measured - predicted);
  y_.push_back(measured);
  e2_.push_back(e2);
  sum_y_ += measured;
  sum_y2_ += measured * measured;
  sum_e2_ += e2;
  if (y_.size() > span_) {
    sum_y_ -= y_.front();
    sum_y2_ -= y_.front() * y_.front();
    y_.pop_front();
  }
  if (e2_.size() > window_) {
    sum_e2_ -= e2_.front();
    e2_.pop_front();
  }
  // Running sums that add and subtract for hours drift; summing afresh once per span bounds it.
  if (++since_resum_ >= span_) Resum();
}

void TrackingAccuracy::Resum() {
  sum_y_ = sum_y2_ = sum_e2_ = 0.0;
  for (const double y : y_) {
    sum_y_ += y;
    sum_y2_ += y * y;
  }
  for (const double e2 : e2_) sum_e2_ += e2;
  since_resum_ = 0;
}

double TrackingAccuracy::fit_percent() const {
  if (!ready()) return std::numeric_limits<double>::quiet_NaN();
  const double n = static_cast<double>(y_.size());
  const double mean = sum_y_ / n;
  const double var = sum_y2_ / n - mean * mean;
  if (!(var > 0.0)) return std::numeric_limits<double>::quiet_NaN();
  const double rmse = std::sqrt(std::max(0.0, sum_e2_) / static_cast<double>(e2_.size()));
  return 100.0 * (1.0 - rmse / std::sqrt(var));
}

}  // namespace odonata::metrics

#include "metrics/running_accuracy.hpp"

#include <cmath>
#include <limits>

namespace odonata::metrics {

void CumulativeAccuracy::Add(double y, double yhat) {
  ++n_;
  const double e = y - yhat;
  const double dy = y - mean_y_;
  mean_y_ += dy / n_;
  m2_y_ += dy * (y - mean_y_);
  const double de = e - mean_e_;
  mean_e_ += de / n_;
  m2_e_ += de * (e - mean_e_);
  sum_e2_ += e * e;
}

Accuracy CumulativeAccuracy::Get() const {
  Accuracy a;
  a.samples = n_;
  if (n_ == 0) return a;
  a.rmse = std::sqrt(sum_e2_ / n_);
  if (m2_y_ > 0) {
    a.fit_percent = 100.0 * (1.0 - std::sqrt(sum_e2_ / m2_y_));
    a.vaf_percent = 100.0 * (1.0 - m2_e_ / m2_y_);
    a.ndei = a.rmse / std::sqrt(m2_y_ / n_);
  } else {
    const double inf = std::numeric_limits<double>::infinity();
    a.fit_percent = a.vaf_percent = sum_e2_ == 0 ? 100.0 : -inf;
    a.ndei = sum_e2_ == 0 ? 0.0 : inf;
  }
  return a;
}

void WindowAccuracy::Add(double y, double yhat) {
  y_.push_back(y);
  yhat_.push_back(yhat);
  while (y_.size() > window_) {
    y_.pop_front();
    yhat_.pop_front();
  }
}

Accuracy WindowAccuracy::Get() const {
  if (y_.empty()) return {};
  Eigen::VectorXd y(static_cast<Eigen::Index>(y_.size())), p(y.size());
  for (std::size_t i = 0; i < y_.size(); ++i) {
    y(static_cast<Eigen::Index>(i)) = y_[i];
    p(static_cast<Eigen::Index>(i)) = yhat_[i];
  }
  return Score(y, p);
}

}  // namespace odonata::metrics

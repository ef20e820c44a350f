#include "plant/wing_beat_averager.hpp"

#include <algorithm>
#include <cmath>

namespace odonata::plant {

WingBeatAverager::WingBeatAverager(double step_s, double max_window_s)
    : step_s_(step_s),
      max_window_s_(max_window_s),
      ring_(static_cast<std::size_t>(std::ceil(max_window_s / step_s)) + 2, WingForceXz::Zero()) {}

void WingBeatAverager::Clear() {
  next_ = 0;
  count_ = 0;
}

void WingBeatAverager::Push(const WingForceXz& step_mean_force_n) {
  ring_[next_] = step_mean_force_n;
  next_ = (next_ + 1) % ring_.size();
  count_ = std::min(count_ + 1, ring_.size());
}

WingForceXz WingBeatAverager::Average(const Eigen::Matrix<double, kWingCount, 1>& window_s) const {
  WingForceXz mean = WingForceXz::Zero();
  if (count_ == 0) return mean;
  for (int w = 0; w < kWingCount; ++w) {
    const double steps = std::min(std::max(window_s(w), step_s_), max_window_s_) / step_s_;
    std::size_t full = static_cast<std::size_t>(steps);
    double fraction = steps - static_cast<double>(full);
    if (full >= count_) {
      full = count_;
      fraction = 0.0;
    }
    double sum_x = 0.0, sum_z = 0.0;
    std::size_t idx = next_;
    for (std::size_t k = 0; k < full; ++k) {
      idx = (idx + ring_.size() - 1) % ring_.size();
      sum_x += ring_[idx](w, 0);
      sum_z += ring_[idx](w, 1);
    }
    if (fraction > 0.0) {
      idx = (idx + ring_.size() - 1) % ring_.size();
      sum_x += fraction * ring_[idx](w, 0);
      sum_z += fraction * ring_[idx](w, 1);
    }
    const double weight = static_cast<double>(full) + fraction;
    mean(w, 0) = sum_x / weight;
    mean(w, 1) = sum_z / weight;
  }
  return mean;
}

}  // namespace odonata::plant

#include "plant/wing_beat_averager.hpp"

namespace odonata::plant {

WingBeatAverager::WingBeatAverager(double step_s, double max_window_s)
    : ring_(step_s, max_window_s, WingForceXz::Zero()) {}

WingForceXz WingBeatAverager::Average(const Eigen::Matrix<double, kWingCount, 1>& window_s) const {
  WingForceXz mean = WingForceXz::Zero();
  if (ring_.empty()) return mean;
  for (int w = 0; w < kWingCount; ++w) {
    double sum_x = 0.0, sum_z = 0.0;
    const double weight = ring_.ForWindow(window_s(w), [&](const WingForceXz& f, double weight) {
      sum_x += weight * f(w, 0);
      sum_z += weight * f(w, 1);
    });
    mean(w, 0) = sum_x / weight;
    mean(w, 1) = sum_z / weight;
  }
  return mean;
}

BeatSignalAverager::BeatSignalAverager(double step_s, double max_window_s)
    : ring_(step_s, max_window_s, BeatVector::Zero()) {}

BeatVector BeatSignalAverager::Average(double window_s) const {
  BeatVector sum = BeatVector::Zero();
  const double weight =
      ring_.ForWindow(window_s, [&sum](const BeatVector& v, double w) { sum += w * v; });
  return weight > 0.0 ? BeatVector(sum / weight) : sum;
}

}  // namespace odonata::plant

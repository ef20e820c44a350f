#pragma once
// The first-order plant the interval tests calibrate on: y(t) = 0.7 y(t−1) + 0.5 u(t−1) + e(t),
// u uniform in [−1, 1], e ~ N(0, σ(u(t−1))²) — one σ, or one per sign of the input.

#include <random>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::fit::testing {

inline sysid::RegressorSpec LinearPlantSpec() {
  sysid::RegressorSpec s;
  s.output_lags = 1;
  s.input_lags = 1;
  s.delay = 1;
  s.outputs = {"y"};
  s.inputs = {"u"};
  return s;
}

/// `samples` of the plant, its noise σ `below` for u(t−1) < 0 and `above` otherwise.
inline sysid::Series LinearPlant(unsigned seed, int samples, double below, double above) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(-1.0, 1.0);
  std::normal_distribution<double> noise(0.0, 1.0);
  sysid::Series s;
  s.outputs = Eigen::MatrixXd::Zero(samples, 1);
  s.inputs = Eigen::MatrixXd::Zero(samples, 1);
  for (int t = 0; t < samples; ++t) s.inputs(t, 0) = level(rng);
  for (int t = 1; t < samples; ++t) {
    const double u = s.inputs(t - 1, 0);
    s.outputs(t, 0) = 0.7 * s.outputs(t - 1, 0) + 0.5 * u + (u < 0 ? below : above) * noise(rng);
  }
  return s;
}

}  // namespace odonata::fit::testing

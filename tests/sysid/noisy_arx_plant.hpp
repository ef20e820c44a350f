#pragma once
// A first-order ARX plant with white equation noise and known parameters: what the tests of each
// rule's uncertainty (estimation/) and of "seen enough" (online/) identify.

#include <random>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid::testing {

/// "pitch" from "servo": one lag of each, delay 1.
inline RegressorSpec PitchFromServo() {
  RegressorSpec s;
  s.output_lags = 1;
  s.input_lags = 1;
  s.delay = 1;
  s.outputs = {"pitch"};
  s.inputs = {"servo"};
  return s;
}

/// y(t) = 0.2 + 0.8 y(t−1) + 0.5 u(t−1) + e(t), e ~ N(0, 0.1²), u uniform on [lo, hi]: gain
/// 0.5 / 0.2 = 2.5, pole 0.8 (time constant −T / ln 0.8 = 0.448 s at T = 0.1 s).
inline Series NoisyFirstOrderPlant(unsigned seed, int samples, double lo = -1.0, double hi = 1.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> level(lo, hi);
  std::normal_distribution<double> noise(0.0, 0.1);
  Series s;
  s.outputs = Eigen::MatrixXd::Zero(samples, 1);
  s.inputs = Eigen::MatrixXd::Zero(samples, 1);
  for (int t = 0; t < samples; ++t) s.inputs(t, 0) = level(rng);
  for (int t = 1; t < samples; ++t)
    s.outputs(t, 0) = 0.2 + 0.8 * s.outputs(t - 1, 0) + 0.5 * s.inputs(t - 1, 0) + noise(rng);
  return s;
}

}  // namespace odonata::sysid::testing

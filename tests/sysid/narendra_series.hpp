#pragma once
// The Narendra–Parthasarathy plant y(k+1) = y(k)/(1+y(k)²) + u(k)³, a standard benchmark.

#include <cmath>
#include <random>

#include "sysid/model/regressor_spec.hpp"

namespace odonata::sysid::testing {

inline Series NarendraSeries(const Eigen::VectorXd& u) {
  Series s;
  s.inputs = u;
  s.outputs = Eigen::MatrixXd::Zero(u.size(), 1);
  for (Eigen::Index k = 0; k + 1 < u.size(); ++k) {
    const double y = s.outputs(k, 0);
    s.outputs(k + 1, 0) = y / (1 + y * y) + std::pow(u(k), 3);
  }
  return s;
}

/// Training: u uniform in [−2, 2], seeded.
inline Series NarendraTrain(int samples = 5000, unsigned seed = 7) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> dist(-2.0, 2.0);
  Eigen::VectorXd u(samples);
  for (int k = 0; k < samples; ++k) u(k) = dist(rng);
  return NarendraSeries(u);
}

/// Validation: u(k) = sin(2πk/100), a different excitation.
inline Series NarendraValidate(int samples = 1000) {
  Eigen::VectorXd u(samples);
  for (int k = 0; k < samples; ++k) u(k) = std::sin(2 * M_PI * k / 100.0);
  return NarendraSeries(u);
}

inline RegressorSpec NarendraSpec() {
  RegressorSpec spec;
  spec.outputs = {"y"};
  spec.inputs = {"u"};
  return spec;
}

}  // namespace odonata::sysid::testing

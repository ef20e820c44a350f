#include "signals/multisine.hpp"

#include <cmath>
#include <stdexcept>

#include <boost/math/constants/constants.hpp>

namespace odonata::signals {
namespace {
constexpr double kPi = boost::math::double_constants::pi;
}

Multisine::Multisine(std::vector<double> frequencies_hz, std::vector<double> amplitudes,
                     std::vector<double> phases_rad)
    : frequencies_hz_(std::move(frequencies_hz)),
      amplitudes_(std::move(amplitudes)),
      phases_rad_(std::move(phases_rad)) {
  if (frequencies_hz_.size() != amplitudes_.size() || amplitudes_.size() != phases_rad_.size()) {
    throw std::invalid_argument("Multisine: frequencies, amplitudes and phases differ in length");
  }
}

Multisine Multisine::Schroeder(std::vector<double> frequencies_hz, double component_amplitude) {
  const std::size_t k_count = frequencies_hz.size();
  std::vector<double> phases(k_count);
  for (std::size_t k = 0; k < k_count; ++k) {
    const double k1 = static_cast<double>(k + 1);
    phases[k] = -kPi * k1 * (k1 - 1.0) / static_cast<double>(k_count);
  }
  return Multisine(std::move(frequencies_hz), std::vector<double>(k_count, component_amplitude),
                   std::move(phases));
}

double Multisine::Value(double t_s) const {
  double sum = 0.0;
  for (std::size_t k = 0; k < frequencies_hz_.size(); ++k) {
    sum += amplitudes_[k] * std::sin(2.0 * kPi * frequencies_hz_[k] * t_s + phases_rad_[k]);
  }
  return sum;
}

double Multisine::PeakBound() const {
  double bound = 0.0;
  for (const double a : amplitudes_) bound += std::fabs(a);
  return bound;
}

}  // namespace odonata::signals

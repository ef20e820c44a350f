#include "signals/gaussian_noise.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include <boost/math/constants/constants.hpp>

namespace odonata::signals {

GaussianNoise::GaussianNoise(double power_w, std::uint64_t seed)
    : power_w_(power_w),
      stddev_(std::sqrt(power_w)),
      clip_sigmas_(std::numeric_limits<double>::infinity()),
      rng_(seed) {
  if (!(power_w >= 0.0)) throw std::invalid_argument("GaussianNoise: power_w must be >= 0");
}

GaussianNoise::GaussianNoise(double power_w, std::uint64_t seed, double clip_sigmas)
    : GaussianNoise(power_w, seed) {
  if (!(clip_sigmas >= 1.0)) throw std::invalid_argument("GaussianNoise: clip_sigmas must be >= 1");
  const double c = clip_sigmas;
  const double pdf = std::exp(-0.5 * c * c) / std::sqrt(2.0 * boost::math::double_constants::pi);
  const double mass = std::erf(c / std::sqrt(2.0));  // 2Φ(c) − 1
  stddev_ = std::sqrt(power_w / (1.0 - 2.0 * c * pdf / mass));
  clip_sigmas_ = c;
}

double GaussianNoise::Next() {
  double z = NextStandard();
  while (std::abs(z) > clip_sigmas_) z = NextStandard();
  return stddev_ * z;
}

double GaussianNoise::NextStandard() {
  if (has_spare_) {
    has_spare_ = false;
    return spare_;
  }
  // u1 ∈ (0, 1] so log(u1) is finite; u2 ∈ [0, 1).
  const double u1 = (static_cast<double>(rng_() >> 11) + 1.0) * 0x1.0p-53;
  const double u2 = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
  const double radius = std::sqrt(-2.0 * std::log(u1));
  const double angle = 6.28318530717958647692 * u2;
  spare_ = radius * std::sin(angle);
  has_spare_ = true;
  return radius * std::cos(angle);
}

std::vector<double> GaussianNoise::Generate(std::size_t count) {
  std::vector<double> out(count);
  for (double& x : out) x = Next();
  return out;
}

}  // namespace odonata::signals

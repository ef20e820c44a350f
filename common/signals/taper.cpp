#include "signals/taper.hpp"

#include <cmath>

#include <boost/math/constants/constants.hpp>

namespace odonata::signals {

double TukeyEnvelope(double t_s, double duration_s, double ramp_s) {
  if (t_s < 0.0 || t_s > duration_s) return 0.0;
  if (ramp_s <= 0.0) return 1.0;
  constexpr double kPi = boost::math::double_constants::pi;
  if (t_s < ramp_s) return 0.5 * (1.0 - std::cos(kPi * t_s / ramp_s));
  if (t_s > duration_s - ramp_s) return 0.5 * (1.0 - std::cos(kPi * (duration_s - t_s) / ramp_s));
  return 1.0;
}

}  // namespace odonata::signals

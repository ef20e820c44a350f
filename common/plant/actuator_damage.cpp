#include "plant/actuator_damage.hpp"

#include <cmath>
#include <sstream>

namespace odonata::plant {

std::string ActuatorDamage::Problems() const {
  std::ostringstream p;
  if (wing < 0 || wing > kWingCount)
    p << "damaged wing must be 1…4 (0: every wing), not " << wing << "\n";
  if (!(amplitude_scale > 0.0 && amplitude_scale <= 1.0))
    p << "amplitude scale must be in (0, 1], not " << amplitude_scale << "\n";
  if (!(frequency_scale > 0.0 && frequency_scale <= 1.0))
    p << "frequency scale must be in (0, 1], not " << frequency_scale << "\n";
  if (std::isnan(at_s) || at_s < 0.0) p << "damage time must be ≥ 0 s, not " << at_s << "\n";
  std::string s = p.str();
  if (!s.empty()) s.pop_back();
  return s;
}

CommandMatrix ActuatorDamage::Apply(const CommandMatrix& commanded, double t_s) const {
  if (!active(t_s)) return commanded;
  CommandMatrix delivered = commanded;
  for (int w = 0; w < kWingCount; ++w) {
    if (wing != 0 && w != wing - 1) continue;
    delivered(w, kStrokeAmplitude) *= amplitude_scale;
    delivered(w, kFlapFrequency) *= frequency_scale;
  }
  return delivered;
}

}  // namespace odonata::plant

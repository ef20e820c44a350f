#pragma once
// A wing that stops delivering what it is commanded: the damage scenario of the online
// identification experiments (docs/plant.md §2). The commanded values are what a controller,
// and so the identifier, sees; the plant flies the delivered ones.

#include <limits>
#include <string>

#include "plant/wing_command.hpp"

namespace odonata::plant {

struct ActuatorDamage {
  double at_s = std::numeric_limits<double>::infinity();  ///< when it happens (never by default)
  int wing = 1;                  ///< 1…4, or 0 for every wing (a sagging battery slows all four)
  double amplitude_scale = 1.0;  ///< delivered φ₀ = scale · commanded φ₀ (0.7: 30 % lost)
  double frequency_scale = 1.0;  ///< delivered f = scale · commanded f (a sagging battery)

  /// Every problem, one per line ("" when valid).
  std::string Problems() const;
  bool active(double t_s) const { return t_s >= at_s; }
  /// The command the damaged vehicle actually flies at time t_s.
  CommandMatrix Apply(const CommandMatrix& commanded, double t_s) const;
};

}  // namespace odonata::plant

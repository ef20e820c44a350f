#pragma once
// A slow "safety pilot" that keeps roll and pitch near level during free-flight experiments.

#include "plant/dimav_plant.hpp"
#include "plant/wing_command.hpp"

namespace odonata::vehicle {

/// Gains of the attitude hold, in rad of stroke-amplitude differential per rad (and per rad/s).
struct AttitudeHoldGains {
  double roll_kp{};     ///< rad φ₀ per rad roll
  double roll_kd_s{};   ///< rad φ₀ per rad/s roll rate
  double pitch_kp{};    ///< rad φ₀ per rad pitch
  double pitch_kd_s{};  ///< rad φ₀ per rad/s pitch rate
};

/// The gains the free-flight presets use, tuned on the default 40 g plant: hover is open-loop
/// unstable in roll and pitch (a roll error doubles in ≈ 0.3 s once the aerodynamic coupling with
/// V_b is modelled), so free-flight data needs a stabiliser, as a flight test needs a safety pilot.
/// Roll uses proportional action only: a roll-rate term (on top of the strong aerodynamic roll
/// damping) made the lateral mode worse in simulation. The identified loops are therefore the
/// held vehicle, excited through the same channel the hold acts on.
AttitudeHoldGains DefaultAttitudeHoldGains();

/// Adds the hold's corrections to `command`: roll uses the left (1, 2) / right (3, 4) φ₀
/// differential, pitch the front (1, 4) / back (2, 3) differential (pitch is nose-down positive,
/// so a positive pitch error raises the front wings' amplitude).
/// Corrections are added on top of whatever excitation `command` already carries; the result is
/// not clamped (the plant clamps).
plant::CommandMatrix ApplyAttitudeHold(const AttitudeHoldGains& gains,
                                       const plant::CommandMatrix& command,
                                       const plant::PlantOutput& output);

}  // namespace odonata::vehicle

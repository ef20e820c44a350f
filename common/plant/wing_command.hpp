#pragma once
// The per-wing command u = [β, f, φ₀, θ_m, θ₀, Δφ] and the 4 × 6 command matrix of the vehicle.

#include <Eigen/Core>
#include <array>
#include <string>

namespace odonata::plant {

/// Number of wings (actuators). Order: 1 fore-left, 2 hind-left, 3 hind-right, 4 fore-right.
inline constexpr int kWingCount = 4;
/// Number of command inputs per wing.
inline constexpr int kCommandsPerWing = 6;

/// Column index of each input in a CommandMatrix row (the paper's order u = [β f φ₀ θ_m θ₀ Δφ]).
enum CommandIndex : int {
  kStrokePlaneAngle =
      0,               ///< β, stroke-plane angle (rad); tilts the stroke-plane normal towards +x.
  kFlapFrequency = 1,  ///< f, flapping frequency (Hz).
  kStrokeAmplitude = 2,  ///< φ₀, stroke amplitude (rad): φ(t) = φ₀ cos(Φ(t)).
  kPitchMean = 3,        ///< θ_m, mean chord pitch to the stroke plane (rad); π/2 = chord normal.
  kPitchAmplitude = 4,  ///< θ₀, chord pitch amplitude (rad): θ = θ_m − θ₀ sin(Φ + Δφ).
  kPitchPhase = 5,      ///< Δφ, rotational phase of the chord pitch (rad).
};

/// Commands of all four wings: row w = wing w + 1, columns as in CommandIndex.
using CommandMatrix = Eigen::Matrix<double, kWingCount, kCommandsPerWing>;

/// Suffixes of the 24 command column names, in CommandIndex order ("w1_beta_rad" …).
inline const std::array<std::string, kCommandsPerWing>& CommandSuffixes() {
  static const std::array<std::string, kCommandsPerWing> kSuffixes = {
      "beta_rad", "freq_hz", "amp_rad", "pitch_mean_rad", "pitch_amp_rad", "phase_rad"};
  return kSuffixes;
}

/// CSV column name of one command, e.g. CommandColumnName(0, kFlapFrequency) == "w1_freq_hz".
/// @pre 0 ≤ wing < kWingCount, 0 ≤ input < kCommandsPerWing.
inline std::string CommandColumnName(int wing, int input) {
  return "w" + std::to_string(wing + 1) + "_" + CommandSuffixes()[input];
}

/// A command matrix with the same per-wing command on all four wings.
/// @param per_wing the six inputs in CommandIndex order.
inline CommandMatrix UniformCommand(const Eigen::Matrix<double, 1, kCommandsPerWing>& per_wing) {
  return per_wing.replicate<kWingCount, 1>();
}

}  // namespace odonata::plant

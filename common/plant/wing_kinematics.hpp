#pragma once
// Prescribed wing motion (paper eq. 1–2, corrected) and the resulting wing frame in the body frame.

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace odonata::plant {

/// Stroke and chord-pitch angles of one wing at one instant.
struct WingAngles {
  double stroke_rad{};         ///< φ = φ₀ cos Φ
  double stroke_rate_radps{};  ///< φ̇ = −φ₀ 2πf sin Φ (quasi-steady: φ₀ held over the sample)
  double pitch_rad{};          ///< θ = θ_m − θ₀ sin(Φ + Δφ), chord to stroke plane
  double pitch_rate_radps{};  ///< θ̇ = −θ₀ 2πf cos(Φ + Δφ)
};

/// Evaluates eq. 1 (with 2πf, not πf) and eq. 2 at the integrated stroke phase Φ.
/// @param phase_rad Φ, the integral of 2πf dt plus the wing's fore/hind offset (rad).
/// @param freq_hz f (Hz); amp_rad φ₀; pitch_mean_rad θ_m; pitch_amp_rad θ₀; pitch_phase_rad Δφ.
WingAngles EvaluateWingAngles(double phase_rad, double freq_hz, double amp_rad,
                              double pitch_mean_rad, double pitch_amp_rad, double pitch_phase_rad);

/// Orthonormal wing frame in the body frame (FLU: x forward, y left, z up).
///
/// Stroke plane: normal n̂ = (sin β, 0, cos β), downstroke direction d̂ = (cos β, 0, −sin β).
/// Span ŝ = cos φ ŝ₀ − sin φ d̂ with ŝ₀ = ±ŷ (left wings +ŷ), so φ̇ < 0 moves the wing along +d̂
/// (the downstroke) on both sides and left/right wings are exact mirror images.
/// Chord (trailing to leading edge) ĉ = cos θ d̂ₗ + sin θ n̂ with d̂ₗ = sin φ ŝ₀ + cos φ d̂ the local
/// downstroke direction; the chord normal ĉ⊥ = ∂ĉ/∂θ = −sin θ d̂ₗ + cos θ n̂.
struct WingFrame {
  Eigen::Vector3d span{};          ///< ŝ, hinge to tip (unit)
  Eigen::Vector3d chord{};         ///< ĉ (unit)
  Eigen::Vector3d chord_normal{};  ///< ĉ⊥ (unit), direction in which ĉ turns when θ grows
};

/// Computes the wing frame for stroke-plane angle β, stroke angle φ and chord pitch θ.
/// @param side_sign +1 for a left wing (root span +ŷ), −1 for a right wing.
WingFrame ComputeWingFrame(double stroke_plane_rad, double stroke_rad, double pitch_rad,
                           double side_sign);

}  // namespace odonata::plant

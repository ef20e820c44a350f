#pragma once
// Quasi-steady aerodynamic coefficients of a flapping plate (Dickinson, Lehmann & Sane 1999 fits,
// as quoted by Z. J. Wang), with the brackets that eq. 3 of the paper lost put back.

#include <array>

namespace odonata::plant {

/// Translational lift coefficient C_L(α) = 0.225 + 1.58 sin(2.13α − 7.20°), α in degrees inside.
/// @param alpha_rad angle of attack in rad, the acute angle between chord and relative velocity.
/// @pre 0 ≤ alpha_rad ≤ π/2 (the fit is only meaningful there; values outside are not clipped).
double LiftCoefficient(double alpha_rad);

/// Translational drag coefficient C_D(α) = 1.92 − 1.55 cos(2.04α − 9.82°), α in degrees inside.
/// @param alpha_rad angle of attack in rad. @pre 0 ≤ alpha_rad ≤ π/2.
double DragCoefficient(double alpha_rad);

/// Rotational-circulation coefficient C_rot = π(0.75 − x̂₀) (Sane & Dickinson 2002).
/// @param pitch_axis_chords x̂₀, the pitch axis measured from the leading edge in chords (0.25 ⇒
/// π/2).
double RotationalForceCoefficient(double pitch_axis_chords);

/// Fast, smooth evaluation of C_L and C_D for the blade-element inner loop.
///
/// The inner loop knows the relative velocity in chord coordinates (v_c along the chord, v_n along
/// the chord normal), not α. Instead of atan2 + sin + cos per strip, the coefficients are tabulated
/// against u = |v_n| / (|v_c| + |v_n|) ∈ [0, 1], a smooth monotonic function of α
/// (α = atan2(u, 1 − u)), and interpolated with cubic Hermite splines (C¹, so RK4 keeps its order).
/// With kIntervals = 512 the error is below 1e-9 everywhere (checked by the tests).
class AeroCoefficientTable {
 public:
  /// Number of table intervals on u ∈ [0, 1].
  static constexpr int kIntervals = 512;

  /// Builds the table from LiftCoefficient and DragCoefficient.
  AeroCoefficientTable();

  /// Writes C_L and C_D for the ratio u = |v_n| / (|v_c| + |v_n|).
  /// @pre 0 ≤ u ≤ 1 (values outside are clamped).
  void Evaluate(double u, double* lift_coefficient, double* drag_coefficient) const {
    double x = u * kIntervals;
    x = x < 0.0 ? 0.0 : (x > kIntervals ? kIntervals : x);
    int i = static_cast<int>(x);
    if (i >= kIntervals) i = kIntervals - 1;
    const double t = x - i;
    const double t2 = t * t;
    const double t3 = t2 * t;
    const double h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
    const double h01 = 1.0 - h00;
    const double h10 = (t3 - 2.0 * t2 + t) * kStepU;
    const double h11 = (t3 - t2) * kStepU;
    const Node& a = nodes_[i];
    const Node& b = nodes_[i + 1];
    *lift_coefficient = h00 * a.cl + h01 * b.cl + h10 * a.dcl_du + h11 * b.dcl_du;
    *drag_coefficient = h00 * a.cd + h01 * b.cd + h10 * a.dcd_du + h11 * b.dcd_du;
  }

  /// Angle of attack (rad) corresponding to the table variable u: α = atan2(u, 1 − u).
  static double AlphaFromRatio(double u);

 private:
  static constexpr double kStepU = 1.0 / kIntervals;
  /// Coefficient values and their u-derivatives at one table node.
  struct Node {
    double cl{};
    double cd{};
    double dcl_du{};
    double dcd_du{};
  };
  std::array<Node, kIntervals + 1> nodes_{};  // nodes at u = i / kIntervals
};

}  // namespace odonata::plant

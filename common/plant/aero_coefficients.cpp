#include "plant/aero_coefficients.hpp"

#include <cmath>

#include "plant/angle_constants.hpp"

namespace odonata::plant {
double LiftCoefficient(double alpha_rad) {
  const double alpha_deg = alpha_rad * kDegPerRad;
  return 0.225 + 1.58 * std::sin((2.13 * alpha_deg - 7.20) * kRadPerDeg);
}

double DragCoefficient(double alpha_rad) {
  const double alpha_deg = alpha_rad * kDegPerRad;
  return 1.92 - 1.55 * std::cos((2.04 * alpha_deg - 9.82) * kRadPerDeg);
}

double RotationalForceCoefficient(double pitch_axis_chords) {
  return kPi * (0.75 - pitch_axis_chords);
}

double AeroCoefficientTable::AlphaFromRatio(double u) { return std::atan2(u, 1.0 - u); }

AeroCoefficientTable::AeroCoefficientTable() {
  for (int i = 0; i <= kIntervals; ++i) {
    const double u = static_cast<double>(i) / kIntervals;
    const double alpha_rad = AlphaFromRatio(u);
    // dα/du for α = atan2(u, 1 − u); chain rule gives the u-slopes the Hermite spline needs.
    const double dalpha_du = 1.0 / (u * u + (1.0 - u) * (1.0 - u));
    const double alpha_deg = alpha_rad * kDegPerRad;
    const double dcl_dalpha = 1.58 * 2.13 * std::cos((2.13 * alpha_deg - 7.20) * kRadPerDeg);
    const double dcd_dalpha = 1.55 * 2.04 * std::sin((2.04 * alpha_deg - 9.82) * kRadPerDeg);
    nodes_[i] = Node{LiftCoefficient(alpha_rad), DragCoefficient(alpha_rad), dcl_dalpha * dalpha_du,
                     dcd_dalpha * dalpha_du};
  }
}

}  // namespace odonata::plant

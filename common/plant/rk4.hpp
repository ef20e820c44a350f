#pragma once
// Classic fixed-step fourth-order Runge–Kutta.

#include <Eigen/Core>

namespace odonata::plant {

/// Advances x' = f(τ, x) by one step h from τ = 0 (τ is the time since the step start, in s).
/// The stage weights (1, 2, 2, 1)/6 are also passed to `f` as the last argument, so a caller can
/// accumulate the Simpson average of any by-product (the wing forces) over the step.
/// @tparam F callable `Vector(double tau_s, const Vector& x, double weight)`.
/// @pre h_s > 0.
template <int N, class F>
Eigen::Matrix<double, N, 1> Rk4Step(F&& f, const Eigen::Matrix<double, N, 1>& x, double h_s) {
  using Vector = Eigen::Matrix<double, N, 1>;
  const Vector k1 = f(0.0, x, 1.0 / 6.0);
  const Vector k2 = f(0.5 * h_s, Vector(x + 0.5 * h_s * k1), 2.0 / 6.0);
  const Vector k3 = f(0.5 * h_s, Vector(x + 0.5 * h_s * k2), 2.0 / 6.0);
  const Vector k4 = f(h_s, Vector(x + h_s * k3), 1.0 / 6.0);
  return x + (h_s / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
}

}  // namespace odonata::plant

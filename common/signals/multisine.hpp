#pragma once
// Sum of sinusoids.

#include <vector>

namespace odonata::signals {

/// x(t) = Σ_k A_k sin(2π f_k t + φ_k).
class Multisine {
 public:
  /// @pre the three vectors have the same length.
  Multisine(std::vector<double> frequencies_hz, std::vector<double> amplitudes,
            std::vector<double> phases_rad);
  /// Equal-amplitude multisine with Schroeder phases φ_k = −π k(k−1)/K (low crest factor), each
  /// component of amplitude `component_amplitude`.
  static Multisine Schroeder(std::vector<double> frequencies_hz, double component_amplitude);
  /// Value at time t_s (s).
  double Value(double t_s) const;
  /// Σ |A_k|: a bound on |x(t)|.
  double PeakBound() const;

 private:
  std::vector<double> frequencies_hz_, amplitudes_, phases_rad_;
};

}  // namespace odonata::signals

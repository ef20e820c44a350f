#pragma once
// White Gaussian noise specified by its power.

#include <cstdint>
#include <random>
#include <vector>

namespace odonata::signals {

/// Zero-mean white Gaussian noise whose power is given in watts, with the 1-ohm convention of
/// MATLAB/Simulink ("noise power" blocks): the signal is read as a voltage across 1 Ω, so power =
/// mean square = variance, and the standard deviation is √P in the signal's own unit. The paper's
/// "0.01 W" is therefore a variance of 0.01 (σ = 0.1).
///
/// Uses a local std::mt19937_64 (its output sequence is fixed by the C++ standard) and the
/// Box–Muller transform written out here, so a seed gives the same numbers on every platform
/// (std::normal_distribution is implementation-defined).
class GaussianNoise {
 public:
  /// @pre power_w ≥ 0.
  GaussianNoise(double power_w, std::uint64_t seed);
  /// Truncated at ±clip_sigmas standard deviations (draws beyond are redrawn), with σ raised so
  /// the power is still power_w: σ² = P / (1 − 2cφ(c) / (2Φ(c) − 1)). An excitation that must
  /// stay inside actuator limits gets its stated power without a clamp distorting it.
  /// @pre power_w ≥ 0, clip_sigmas ≥ 1.
  GaussianNoise(double power_w, std::uint64_t seed, double clip_sigmas);
  /// Next sample.
  double Next();
  /// The next `count` samples.
  std::vector<double> Generate(std::size_t count);
  double power_w() const { return power_w_; }
  double stddev() const { return stddev_; }
  /// The largest |sample|, or +∞ when not truncated.
  double bound() const { return clip_sigmas_ * stddev_; }

 private:
  double power_w_{};
  double stddev_{};
  double clip_sigmas_;  // +∞: plain Gaussian
  std::mt19937_64 rng_;
  bool has_spare_{false};
  double spare_{};

  double NextStandard();
};

}  // namespace odonata::signals

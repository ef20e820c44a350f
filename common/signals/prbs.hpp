#pragma once
// Pseudo-random binary sequence from a maximal-length linear-feedback shift register.

#include <cstdint>
#include <vector>

namespace odonata::signals {

/// PRBS of ±amplitude: a Galois LFSR of order n (period 2ⁿ − 1 bits) clocked every
/// `samples_per_bit` samples. The seed only selects the (non-zero) initial register, so the
/// sequence is deterministic for a given seed.
class Prbs {
 public:
  /// @pre 3 ≤ order ≤ 31, samples_per_bit ≥ 1.
  Prbs(int order, int samples_per_bit, double amplitude, std::uint64_t seed);
  /// The next `count` samples (continues where the previous call stopped).
  std::vector<double> Generate(std::size_t count);
  /// Sequence period in bits, 2ⁿ − 1.
  std::uint64_t period_bits() const { return (std::uint64_t{1} << order_) - 1; }

 private:
  int order_{};
  int samples_per_bit_{};
  double amplitude_{};
  std::uint32_t register_{};
  std::uint32_t taps_{};
  int sample_in_bit_{0};
  double current_{};
};

}  // namespace odonata::signals

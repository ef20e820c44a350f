#pragma once
// Amplitude-modulated pseudo-random binary sequence (APRBS): random levels held for random
// times. Where a chirp visits each amplitude only briefly, an APRBS holds levels across the whole
// input range long enough for the output to settle, which is what a nonlinear static map or a
// state-dependent gain needs to be seen (docs/identifier.md §11).

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace odonata::signals {

struct AprbsOptions {
  double low = -1.0;  ///< levels are drawn uniformly from [low, high]
  double high = 1.0;
  int hold_min = 1;  ///< each level is held a whole number of samples in [hold_min, hold_max]
  int hold_max = 1;
  /// Trailing moving average over this many samples (≤ 1: none), so the steps stay inside the
  /// band of an excitation whose plant must not be kicked (free flight).
  int smooth = 1;
};

/// Problems of the options, one per line ("" when valid).
std::string AprbsProblems(const AprbsOptions& options);

/// The first `samples` values of the APRBS of `seed`. Deterministic on every platform: levels
/// and hold lengths come from std::mt19937_64 through fixed arithmetic, not through the
/// implementation-defined standard distributions. Starts with a new level at sample 0, so with
/// hold_min = hold_max = L the levels are aligned to blocks of L samples.
/// @throws std::invalid_argument when AprbsProblems(options) is not empty.
std::vector<double> AprbsSequence(std::size_t samples, const AprbsOptions& options,
                                  std::uint64_t seed);

}  // namespace odonata::signals

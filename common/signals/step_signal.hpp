#pragma once
// Steps: a single step and a seeded random staircase.

#include <cstdint>
#include <vector>

namespace odonata::signals {

/// x(t) = before for t < step_time_s, after for t ≥ step_time_s.
class StepSignal {
 public:
  StepSignal(double step_time_s, double before, double after);
  /// Value at time t_s (s).
  double Value(double t_s) const { return t_s < step_time_s_ ? before_ : after_; }

 private:
  double step_time_s_{}, before_{}, after_{};
};

/// Random staircase: levels drawn uniformly from [−amplitude, amplitude], each held for
/// `hold_samples` samples; seeded with a local std::mt19937_64 (53-bit uniforms, portable).
/// @pre hold_samples ≥ 1.
std::vector<double> RandomSteps(std::size_t count, std::size_t hold_samples, double amplitude,
                                std::uint64_t seed);

}  // namespace odonata::signals

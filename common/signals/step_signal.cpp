#include "signals/step_signal.hpp"

#include <random>
#include <stdexcept>

namespace odonata::signals {

StepSignal::StepSignal(double step_time_s, double before, double after)
    : step_time_s_(step_time_s), before_(before), after_(after) {}

std::vector<double> RandomSteps(std::size_t count, std::size_t hold_samples, double amplitude,
                                std::uint64_t seed) {
  if (hold_samples < 1) throw std::invalid_argument("RandomSteps: hold_samples must be >= 1");
  std::mt19937_64 rng(seed);
  std::vector<double> out(count);
  double level = 0.0;
  for (std::size_t i = 0; i < count; ++i) {
    if (i % hold_samples == 0) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1), portable
      level = amplitude * (2.0 * u - 1.0);
    }
    out[i] = level;
  }
  return out;
}

}  // namespace odonata::signals

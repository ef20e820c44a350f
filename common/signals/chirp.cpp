#include "signals/chirp.hpp"

#include <cmath>
#include <stdexcept>

namespace odonata::signals {
namespace {
constexpr double kTwoPi = 6.28318530717958647692;
}

LinearChirp::LinearChirp(double start_hz, double end_hz, double amplitude, double duration_s,
                         double phase_rad)
    : start_hz_(start_hz),
      end_hz_(end_hz),
      amplitude_(amplitude),
      duration_s_(duration_s),
      phase_rad_(phase_rad) {
  if (!(duration_s > 0.0) || !(start_hz >= 0.0) || !(end_hz >= 0.0)) {
    throw std::invalid_argument("LinearChirp: need duration_s > 0 and frequencies >= 0");
  }
}

double LinearChirp::Value(double t_s) const {
  if (t_s < 0.0 || t_s > duration_s_) return 0.0;
  const double cycles = start_hz_ * t_s + (end_hz_ - start_hz_) * t_s * t_s / (2.0 * duration_s_);
  return amplitude_ * std::sin(phase_rad_ + kTwoPi * cycles);
}

double LinearChirp::FrequencyHz(double t_s) const {
  return start_hz_ + (end_hz_ - start_hz_) * t_s / duration_s_;
}

LogChirp::LogChirp(double start_hz, double end_hz, double amplitude, double duration_s,
                   double phase_rad)
    : start_hz_(start_hz),
      end_hz_(end_hz),
      amplitude_(amplitude),
      duration_s_(duration_s),
      phase_rad_(phase_rad) {
  if (!(duration_s > 0.0) || !(start_hz > 0.0) || !(end_hz > 0.0)) {
    throw std::invalid_argument("LogChirp: need duration_s > 0 and frequencies > 0");
  }
}

double LogChirp::Value(double t_s) const {
  if (t_s < 0.0 || t_s > duration_s_) return 0.0;
  const double ratio = end_hz_ / start_hz_;
  double cycles;
  if (std::fabs(ratio - 1.0) < 1e-12) {
    cycles = start_hz_ * t_s;  // degenerate: constant frequency
  } else {
    const double log_ratio = std::log(ratio);
    cycles = start_hz_ * duration_s_ * std::expm1(log_ratio * t_s / duration_s_) / log_ratio;
  }
  return amplitude_ * std::sin(phase_rad_ + kTwoPi * cycles);
}

double LogChirp::FrequencyHz(double t_s) const {
  return start_hz_ * std::pow(end_hz_ / start_hz_, t_s / duration_s_);
}

}  // namespace odonata::signals

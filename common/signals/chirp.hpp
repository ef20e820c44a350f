#pragma once
// Swept sines: linear and logarithmic (exponential) chirps.

namespace odonata::signals {

/// Linear chirp x(t) = A sin(φ₀ + 2π (f₀ t + (f₁ − f₀) t² / (2T))) for 0 ≤ t ≤ T, 0 outside.
/// Instantaneous frequency f₀ + (f₁ − f₀) t / T.
class LinearChirp {
 public:
  /// @pre duration_s > 0, start_hz ≥ 0, end_hz ≥ 0. amplitude in the unit of the signal.
  LinearChirp(double start_hz, double end_hz, double amplitude, double duration_s,
              double phase_rad = 0.0);
  /// Value at time t_s (s).
  double Value(double t_s) const;
  /// Instantaneous frequency (Hz) at t_s.
  double FrequencyHz(double t_s) const;

 private:
  double start_hz_{}, end_hz_{}, amplitude_{}, duration_s_{}, phase_rad_{};
};

/// Logarithmic chirp: instantaneous frequency f₀ (f₁/f₀)^(t/T), so each octave takes equal time;
/// x(t) = A sin(φ₀ + 2π f₀ T (k^(t/T) − 1) / ln k), k = f₁/f₀, for 0 ≤ t ≤ T, 0 outside.
class LogChirp {
 public:
  /// @pre duration_s > 0, start_hz > 0, end_hz > 0.
  LogChirp(double start_hz, double end_hz, double amplitude, double duration_s,
           double phase_rad = 0.0);
  /// Value at time t_s (s).
  double Value(double t_s) const;
  /// Instantaneous frequency (Hz) at t_s.
  double FrequencyHz(double t_s) const;

 private:
  double start_hz_{}, end_hz_{}, amplitude_{}, duration_s_{}, phase_rad_{};
};

}  // namespace odonata::signals

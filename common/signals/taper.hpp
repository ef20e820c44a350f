#pragma once
// Fade-in / fade-out envelope for excitation signals.

namespace odonata::signals {

/// Tukey (raised-cosine) envelope on [0, duration_s]: rises from 0 to 1 over ramp_s, stays 1, falls
/// back to 0 over the last ramp_s; 0 outside. Fading an excitation in and out keeps the integral of
/// a zero-mean input near zero, so an integrating plant (attitude) does not drift.
/// @pre duration_s > 0, 0 ≤ ramp_s ≤ duration_s / 2.
double TukeyEnvelope(double t_s, double duration_s, double ramp_s);

}  // namespace odonata::signals

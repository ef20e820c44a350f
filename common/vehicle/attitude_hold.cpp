#include "vehicle/attitude_hold.hpp"

namespace odonata::vehicle {

AttitudeHoldGains DefaultAttitudeHoldGains() { return AttitudeHoldGains{0.3, 0.0, 0.4, 0.02}; }

plant::CommandMatrix ApplyAttitudeHold(const AttitudeHoldGains& gains,
                                       const plant::CommandMatrix& command,
                                       const plant::PlantOutput& output) {
  plant::CommandMatrix c = command;
  const double roll =
      -(gains.roll_kp * output.roll_rad + gains.roll_kd_s * output.rate_body_radps.x());
  const double pitch =
      gains.pitch_kp * output.pitch_rad + gains.pitch_kd_s * output.rate_body_radps.y();
  c(0, plant::kStrokeAmplitude) += roll + pitch;   // fore-left
  c(1, plant::kStrokeAmplitude) += roll - pitch;   // hind-left
  c(2, plant::kStrokeAmplitude) += -roll - pitch;  // hind-right
  c(3, plant::kStrokeAmplitude) += -roll + pitch;  // fore-right
  return c;
}

}  // namespace odonata::vehicle

#include "vehicle/wing_channels.hpp"

namespace odonata::vehicle {
namespace {

using plant::CommandMatrix;
using plant::kStrokeAmplitude;
using plant::kStrokePlaneAngle;

// Mean of a command entry over a pair of wings (exact when the two are equal).
double PairMean(const CommandMatrix& c, const int (&wings)[2], int input) {
  return 0.5 * (c(wings[0], input) + c(wings[1], input));
}

}  // namespace

double VerticalChannelRad(const CommandMatrix& c, double trim_amp_rad) {
  return 0.5 * (PairMean(c, kLeft, kStrokeAmplitude) + PairMean(c, kRight, kStrokeAmplitude)) -
         trim_amp_rad;
}

double RollChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kLeft, kStrokeAmplitude) - PairMean(c, kRight, kStrokeAmplitude));
}

double PitchChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kFront, kStrokeAmplitude) - PairMean(c, kBack, kStrokeAmplitude));
}

double YawChannelRad(const CommandMatrix& c) {
  return 0.5 * (PairMean(c, kRight, kStrokePlaneAngle) - PairMean(c, kLeft, kStrokePlaneAngle));
}

const std::vector<std::string>& AppliedChannelNames() {
  static const std::vector<std::string> kNames = {"u_vertical_applied_rad", "u_roll_applied_rad",
                                                  "u_pitch_applied_rad", "u_yaw_applied_rad"};
  return kNames;
}

std::vector<double> AppliedChannelValues(const CommandMatrix& applied, double trim_amp_rad) {
  return {VerticalChannelRad(applied, trim_amp_rad), RollChannelRad(applied),
          PitchChannelRad(applied), YawChannelRad(applied)};
}

}  // namespace odonata::vehicle

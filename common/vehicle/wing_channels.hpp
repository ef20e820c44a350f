#pragma once
// The vehicle's four control channels read from its 4 × 6 wing commands (docs/plant.md §12): what
// a preset excites, what the attitude hold corrects, and what a beat state reports as applied.

#include <string>
#include <vector>

#include "plant/wing_command.hpp"

namespace odonata::vehicle {

/// Wing groups (0-based rows): 1 fore-left, 2 hind-left, 3 hind-right, 4 fore-right.
inline constexpr int kLeft[2] = {0, 1};
inline constexpr int kRight[2] = {2, 3};
inline constexpr int kFront[2] = {0, 3};
inline constexpr int kBack[2] = {1, 2};

/// The scalar command channels of the free-flight presets (docs/plant.md §12), read
/// from any command matrix. Excitation columns are these channels of the designed command;
/// *_applied_* columns the same channels of the command actually applied (hold added, clamped).
/// Vertical: mean φ₀ of the four wings minus the trim φ₀ (rad).
double VerticalChannelRad(const plant::CommandMatrix& c, double trim_amp_rad);
/// Roll: half the mean φ₀ of the left wings (1, 2) minus that of the right wings (3, 4) (rad).
double RollChannelRad(const plant::CommandMatrix& c);
/// Pitch: half the mean φ₀ of the front wings (1, 4) minus that of the back wings (2, 3) (rad).
double PitchChannelRad(const plant::CommandMatrix& c);
/// Yaw: half the mean β of the right wings (3, 4) minus that of the left wings (1, 2) (rad).
double YawChannelRad(const plant::CommandMatrix& c);

/// The applied-command columns, in this order: "u_vertical_applied_rad", "u_roll_applied_rad",
/// "u_pitch_applied_rad", "u_yaw_applied_rad".
const std::vector<std::string>& AppliedChannelNames();
/// The four channels of `applied` in AppliedChannelNames() order.
std::vector<double> AppliedChannelValues(const plant::CommandMatrix& applied, double trim_amp_rad);

}  // namespace odonata::vehicle

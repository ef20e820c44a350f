#pragma once
// The plant's output signals by name: the one table behind odonata-sim's CSV columns, the bus
// messages' named fields (messages/) and the names in configs and presets, so a signal is called
// the same everywhere and flattened in one order.

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "plant/dimav_plant.hpp"

namespace odonata::plant {

constexpr std::size_t kStateOutputCount = 20;  ///< 12 body states, fx1..4, fz1..4
constexpr std::size_t kBeatOutputCount = 11;   ///< 9 averaged states, total fx and fz

/// "vx_mps" … "z_m", "fx1_n" … "fx4_n", "fz1_n" … "fz4_n".
const std::vector<std::string>& StateSignalNames();
/// The beat averages, each an instantaneous name with "_avg": "vx_mps_avg" … "yaw_rad_avg", then
/// the four wings' totals "fx_total_n_avg", "fz_total_n_avg".
const std::vector<std::string>& BeatSignalNames();

/// `output` in StateSignalNames() order.
std::array<double, kStateOutputCount> StateSignalValues(const PlantOutput& output);
/// `beat` in BeatSignalNames() order.
std::array<double, kBeatOutputCount> BeatSignalValues(const BeatAverages& beat);

/// Position of `name` in StateSignalNames() / BeatSignalNames(); nullopt when it is not there.
std::optional<std::size_t> StateSignalIndex(const std::string& name);
std::optional<std::size_t> BeatSignalIndex(const std::string& name);

}  // namespace odonata::plant

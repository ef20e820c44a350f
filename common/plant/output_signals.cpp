#include "plant/output_signals.hpp"

#include <algorithm>

namespace odonata::plant {
namespace {
const char* const kBodyStates[12] = {"vx_mps",  "vy_mps",  "vz_mps",   "p_radps",
                                     "q_radps", "r_radps", "roll_rad", "pitch_rad",
                                     "yaw_rad", "x_m",     "y_m",      "z_m"};

std::optional<std::size_t> IndexIn(const std::vector<std::string>& names, const std::string& name) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return std::nullopt;
  return static_cast<std::size_t>(it - names.begin());
}
}  // namespace

const std::vector<std::string>& StateSignalNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n(std::begin(kBodyStates), std::end(kBodyStates));
    for (int w = 1; w <= kWingCount; ++w) n.push_back("fx" + std::to_string(w) + "_n");
    for (int w = 1; w <= kWingCount; ++w) n.push_back("fz" + std::to_string(w) + "_n");
    return n;
  }();
  return names;
}

const std::vector<std::string>& BeatSignalNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (int i = 0; i < 9; ++i) n.push_back(std::string(kBodyStates[i]) + "_avg");
    n.push_back("fx_total_n_avg");
    n.push_back("fz_total_n_avg");
    return n;
  }();
  return names;
}

std::array<double, kStateOutputCount> StateSignalValues(const PlantOutput& o) {
  std::array<double, kStateOutputCount> v{};
  std::size_t c = 0;
  for (int i = 0; i < 3; ++i) v[c++] = o.velocity_body_mps(i);
  for (int i = 0; i < 3; ++i) v[c++] = o.rate_body_radps(i);
  v[c++] = o.roll_rad;
  v[c++] = o.pitch_rad;
  v[c++] = o.yaw_rad;
  for (int i = 0; i < 3; ++i) v[c++] = o.position_m(i);
  for (int w = 0; w < kWingCount; ++w) v[c++] = o.force_x_n(w);
  for (int w = 0; w < kWingCount; ++w) v[c++] = o.force_z_n(w);
  return v;
}

std::array<double, kBeatOutputCount> BeatSignalValues(const BeatAverages& b) {
  std::array<double, kBeatOutputCount> v{};
  std::size_t c = 0;
  for (int i = 0; i < 3; ++i) v[c++] = b.velocity_body_mps(i);
  for (int i = 0; i < 3; ++i) v[c++] = b.rate_body_radps(i);
  v[c++] = b.roll_rad;
  v[c++] = b.pitch_rad;
  v[c++] = b.yaw_rad;
  v[c++] = b.force_x_n;
  v[c++] = b.force_z_n;
  return v;
}

std::optional<std::size_t> StateSignalIndex(const std::string& name) {
  return IndexIn(StateSignalNames(), name);
}

std::optional<std::size_t> BeatSignalIndex(const std::string& name) {
  return IndexIn(BeatSignalNames(), name);
}

}  // namespace odonata::plant

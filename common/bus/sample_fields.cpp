#include "bus/sample_fields.hpp"

#include <cmath>

namespace odonata::bus {
namespace {
const char* const kSuffixes[6] = {"beta_rad",       "freq_hz",       "amp_rad",
                                  "pitch_mean_rad", "pitch_amp_rad", "phase_rad"};
const char* const kStateNames[12] = {"vx_mps",  "vy_mps",  "vz_mps",   "p_radps",
                                     "q_radps", "r_radps", "roll_rad", "pitch_rad",
                                     "yaw_rad", "x_m",     "y_m",      "z_m"};

const double* CommandArray(const odonata::wing_command_t& m, int field) {
  switch (field) {
    case 0:
      return m.beta_rad;
    case 1:
      return m.freq_hz;
    case 2:
      return m.amp_rad;
    case 3:
      return m.pitch_mean_rad;
    case 4:
      return m.pitch_amp_rad;
    default:
      return m.phase_rad;
  }
}

bool Finite(const double* v, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(v[i])) return false;
  return true;
}
}  // namespace

const std::vector<std::string>& CommandFieldNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (int w = 1; w <= 4; ++w)
      for (const char* s : kSuffixes) n.push_back("w" + std::to_string(w) + "_" + s);
    return n;
  }();
  return names;
}

const std::vector<std::string>& BeatFieldNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n;
    for (int i = 0; i < 9; ++i) n.push_back(std::string(kStateNames[i]) + "_avg");
    n.push_back("fx_total_n_avg");
    n.push_back("fz_total_n_avg");
    return n;
  }();
  return names;
}

const std::vector<std::string>& AppliedFieldNames() {
  static const std::vector<std::string> names = {"u_vertical_applied_rad", "u_roll_applied_rad",
                                                 "u_pitch_applied_rad", "u_yaw_applied_rad"};
  return names;
}

std::optional<int> BeatStateOffset(const std::string& name) {
  for (const auto& n : BeatFieldNames())
    if (n == name) return 0;
  for (const auto& n : AppliedFieldNames())
    if (n == name) return 1;
  return std::nullopt;
}

const std::vector<std::string>& StateFieldNames() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> n(std::begin(kStateNames), std::end(kStateNames));
    for (int w = 1; w <= 4; ++w) n.push_back("fx" + std::to_string(w) + "_n");
    for (int w = 1; w <= 4; ++w) n.push_back("fz" + std::to_string(w) + "_n");
    return n;
  }();
  return names;
}

bool IsAveragedSignal(const std::string& name) {
  if (name == "t_s" || name == "window_s") return false;
  for (const auto& n : StateFieldNames())
    if (n == name) return false;
  for (const auto& n : BeatFieldNames())
    if (n == name) return false;
  return true;  // command fields, applied channels and any excitation name
}

std::optional<double> CommandField(const odonata::wing_command_t& m, const std::string& name) {
  if (name.size() > 3 && name[0] == 'w' && name[2] == '_' && name[1] >= '1' && name[1] <= '4') {
    const int wing = name[1] - '1';
    const std::string suffix = name.substr(3);
    for (int f = 0; f < 6; ++f)
      if (suffix == kSuffixes[f]) return CommandArray(m, f)[wing];
  }
  const auto n = std::min<std::size_t>(m.excitation_names.size(), m.excitations.size());
  for (std::size_t i = 0; i < n; ++i)
    if (m.excitation_names[i] == name) return m.excitations[i];
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

std::optional<double> StateField(const odonata::plant_state_t& m, const std::string& name) {
  const double* blocks[4] = {m.velocity_mps, m.rate_radps, m.attitude_rad, m.position_m};
  for (int i = 0; i < 12; ++i)
    if (name == kStateNames[i]) return blocks[i / 3][i % 3];
  if (name.size() == 5 && name[0] == 'f' && (name[1] == 'x' || name[1] == 'z') && name[2] >= '1' &&
      name[2] <= '4' && name.compare(3, 2, "_n") == 0) {
    const int wing = name[2] - '1';
    return name[1] == 'x' ? m.fx_n[wing] : m.fz_n[wing];
  }
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

std::optional<double> BeatStateField(const odonata::beat_state_t& m, const std::string& name) {
  const double* blocks[3] = {m.velocity_mps, m.rate_radps, m.attitude_rad};
  for (int i = 0; i < 9; ++i)
    if (name == BeatFieldNames()[i]) return blocks[i / 3][i % 3];
  const double applied[4] = {m.u_vertical_applied_rad, m.u_roll_applied_rad, m.u_pitch_applied_rad,
                             m.u_yaw_applied_rad};
  for (int i = 0; i < 4; ++i)
    if (name == AppliedFieldNames()[i]) return applied[i];
  if (name == "fx_total_n_avg") return m.fx_total_n;
  if (name == "fz_total_n_avg") return m.fz_total_n;
  if (name == "window_s") return m.window_s;
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

bool AllFinite(const odonata::wing_command_t& m) {
  for (int f = 0; f < 6; ++f)
    if (!Finite(CommandArray(m, f), 4)) return false;
  return std::isfinite(m.t_s) &&
         Finite(m.excitations.data(), static_cast<int>(m.excitations.size()));
}

bool AllFinite(const odonata::plant_state_t& m) {
  return std::isfinite(m.t_s) && Finite(m.velocity_mps, 3) && Finite(m.rate_radps, 3) &&
         Finite(m.attitude_rad, 3) && Finite(m.position_m, 3) && Finite(m.fx_n, 4) &&
         Finite(m.fz_n, 4);
}

bool AllFinite(const odonata::beat_state_t& m) {
  const double scalars[] = {m.t_s,
                            m.window_s,
                            m.fx_total_n,
                            m.fz_total_n,
                            m.u_vertical_applied_rad,
                            m.u_roll_applied_rad,
                            m.u_pitch_applied_rad,
                            m.u_yaw_applied_rad};
  return Finite(scalars, 8) && Finite(m.velocity_mps, 3) && Finite(m.rate_radps, 3) &&
         Finite(m.attitude_rad, 3) && Finite(m.applied_beta_rad, 4) &&
         Finite(m.applied_freq_hz, 4) && Finite(m.applied_amp_rad, 4) &&
         Finite(m.applied_pitch_mean_rad, 4) && Finite(m.applied_pitch_amp_rad, 4) &&
         Finite(m.applied_phase_rad, 4);
}

std::string CountProblems(const odonata::wing_command_t& m) {
  if (m.num_excitations < 0 ||
      static_cast<std::size_t>(m.num_excitations) != m.excitation_names.size() ||
      static_cast<std::size_t>(m.num_excitations) != m.excitations.size()) {
    return "num_excitations disagrees with the excitation arrays";
  }
  return "";
}

}  // namespace odonata::bus

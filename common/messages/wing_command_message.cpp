#include "messages/wing_command_message.hpp"

#include <cmath>

#include "contract/precondition.hpp"

namespace odonata::messages {
namespace {
// The message's six per-wing arrays in plant::CommandIndex order.
template <class Msg>
auto CommandArrays(Msg& m) {
  return std::array{m.beta_rad,       m.freq_hz,       m.amp_rad,
                    m.pitch_mean_rad, m.pitch_amp_rad, m.phase_rad};
}
}  // namespace

plant::CommandMatrix ToCommandMatrix(const odonata::wing_command_t& msg) {
  const auto arrays = CommandArrays(msg);
  plant::CommandMatrix c;
  for (int w = 0; w < plant::kWingCount; ++w)
    for (int i = 0; i < plant::kCommandsPerWing; ++i) c(w, i) = arrays[i][w];
  return c;
}

odonata::wing_command_t ToCommandMessage(const pipeline::CommandSchedule& schedule, std::size_t k,
                                         int64_t utime) {
  ODONATA_EXPECTS(k < schedule.size());
  const plant::CommandMatrix& c = schedule.commands[k];
  odonata::wing_command_t m{};
  m.utime = utime;
  m.seq = static_cast<int64_t>(k);
  m.t_s = schedule.TimeOf(k);
  const auto arrays = CommandArrays(m);
  for (int w = 0; w < plant::kWingCount; ++w)
    for (int i = 0; i < plant::kCommandsPerWing; ++i) arrays[i][w] = c(w, i);
  // encode() trusts the count: keep it equal to both vector sizes.
  m.num_excitations = static_cast<int32_t>(schedule.excitation_names.size());
  m.excitation_names = schedule.excitation_names;
  for (const std::vector<double>& values : schedule.excitation_values) {
    m.excitations.push_back(values[k]);
  }
  m.source = schedule.source;
  return m;
}

std::optional<double> CommandField(const odonata::wing_command_t& m, const std::string& name) {
  if (name.size() > 3 && name[0] == 'w' && name[2] == '_' && name[1] >= '1' &&
      name[1] < '1' + plant::kWingCount) {
    const int wing = name[1] - '1';
    const std::string suffix = name.substr(3);
    for (int i = 0; i < plant::kCommandsPerWing; ++i)
      if (suffix == plant::CommandSuffixes()[i]) return CommandArrays(m)[i][wing];
  }
  const auto n = std::min<std::size_t>(m.excitation_names.size(), m.excitations.size());
  for (std::size_t i = 0; i < n; ++i)
    if (m.excitation_names[i] == name) return m.excitations[i];
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

bool AllFinite(const odonata::wing_command_t& m) {
  for (const double* a : CommandArrays(m))
    for (int w = 0; w < plant::kWingCount; ++w)
      if (!std::isfinite(a[w])) return false;
  for (const double v : m.excitations)
    if (!std::isfinite(v)) return false;
  return std::isfinite(m.t_s);
}

std::string CountProblems(const odonata::wing_command_t& m) {
  if (m.num_excitations < 0 ||
      static_cast<std::size_t>(m.num_excitations) != m.excitation_names.size() ||
      static_cast<std::size_t>(m.num_excitations) != m.excitations.size()) {
    return "num_excitations disagrees with the excitation arrays";
  }
  return "";
}

}  // namespace odonata::messages

#include "messages/beat_state_message.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "experiments/experiment_preset.hpp"
#include "messages/finite_values.hpp"
#include "plant/output_signals.hpp"

namespace odonata::messages {
namespace {
// The applied command's six per-wing arrays in plant::CommandIndex order.
template <class Msg>
auto AppliedArrays(Msg& m) {
  return std::array{m.applied_beta_rad,       m.applied_freq_hz,       m.applied_amp_rad,
                    m.applied_pitch_mean_rad, m.applied_pitch_amp_rad, m.applied_phase_rad};
}

// The applied channels in vehicle::AppliedChannelNames() order.
std::array<double, 4> AppliedChannels(const odonata::beat_state_t& m) {
  return {m.u_vertical_applied_rad, m.u_roll_applied_rad, m.u_pitch_applied_rad,
          m.u_yaw_applied_rad};
}

plant::BeatAverages ToBeatAverages(const odonata::beat_state_t& m) {
  plant::BeatAverages b;
  b.window_s = m.window_s;
  for (int i = 0; i < 3; ++i) {
    b.velocity_body_mps(i) = m.velocity_mps[i];
    b.rate_body_radps(i) = m.rate_radps[i];
  }
  b.roll_rad = m.attitude_rad[0];
  b.pitch_rad = m.attitude_rad[1];
  b.yaw_rad = m.attitude_rad[2];
  b.force_x_n = m.fx_total_n;
  b.force_z_n = m.fz_total_n;
  return b;
}

std::optional<std::size_t> AppliedIndex(const std::string& name) {
  const auto& names = vehicle::AppliedChannelNames();
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) return std::nullopt;
  return static_cast<std::size_t>(it - names.begin());
}

}  // namespace

odonata::beat_state_t ToBeatStateMessage(const pipeline::PlantSample& sample,
                                         const pipeline::VehicleSetup& setup, int64_t utime) {
  const plant::BeatAverages& b = sample.output.beat;
  const plant::CommandMatrix& c = sample.applied_command;
  odonata::beat_state_t m{};
  m.utime = utime;
  m.seq = sample.seq;
  m.command_seq = sample.command_seq;
  m.t_s = sample.output.time_s;
  m.window_s = b.window_s;
  for (int i = 0; i < 3; ++i) {
    m.velocity_mps[i] = b.velocity_body_mps(i);
    m.rate_radps[i] = b.rate_body_radps(i);
  }
  m.attitude_rad[0] = b.roll_rad;
  m.attitude_rad[1] = b.pitch_rad;
  m.attitude_rad[2] = b.yaw_rad;
  m.fx_total_n = b.force_x_n;
  m.fz_total_n = b.force_z_n;
  const auto arrays = AppliedArrays(m);
  for (int w = 0; w < plant::kWingCount; ++w)
    for (int i = 0; i < plant::kCommandsPerWing; ++i) arrays[i][w] = c(w, i);
  const std::vector<double> u =
      vehicle::AppliedChannelValues(c, setup.trim_command(0, plant::kStrokeAmplitude));
  m.u_vertical_applied_rad = u[0];
  m.u_roll_applied_rad = u[1];
  m.u_pitch_applied_rad = u[2];
  m.u_yaw_applied_rad = u[3];
  m.attitude_hold = setup.attitude_hold ? 1 : 0;
  return m;
}

std::optional<int> BeatStateOffset(const std::string& name) {
  if (plant::BeatSignalIndex(name)) return 0;
  if (AppliedIndex(name)) return 1;
  return std::nullopt;
}

std::optional<double> BeatStateField(const odonata::beat_state_t& m, const std::string& name) {
  if (const auto i = plant::BeatSignalIndex(name))
    return plant::BeatSignalValues(ToBeatAverages(m))[*i];
  if (const auto i = AppliedIndex(name)) return AppliedChannels(m)[*i];
  if (name == "window_s") return m.window_s;
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

bool AllFinite(const odonata::beat_state_t& m) {
  const auto applied = AppliedChannels(m);
  const double scalars[] = {m.t_s, m.window_s, m.fx_total_n, m.fz_total_n};
  if (!FiniteValues(scalars, 4) || !FiniteValues(applied.data(), 4)) return false;
  for (const double* a : AppliedArrays(m))
    if (!FiniteValues(a, plant::kWingCount)) return false;
  return FiniteValues(m.velocity_mps, 3) && FiniteValues(m.rate_radps, 3) &&
         FiniteValues(m.attitude_rad, 3);
}

}  // namespace odonata::messages

#include "messages/plant_state_message.hpp"

#include <cmath>

#include "messages/finite_values.hpp"
#include "plant/output_signals.hpp"

namespace odonata::messages {
namespace {
int8_t StatusCode(pipeline::SampleStatus status) {
  switch (status) {
    case pipeline::SampleStatus::kOnGround:
      return odonata::plant_state_t::STATUS_ON_GROUND;
    case pipeline::SampleStatus::kReset:
      return odonata::plant_state_t::STATUS_RESET;
    case pipeline::SampleStatus::kDiverged:
      return odonata::plant_state_t::STATUS_DIVERGED;
    case pipeline::SampleStatus::kOk:
      break;
  }
  return odonata::plant_state_t::STATUS_OK;
}

}  // namespace

odonata::plant_state_t ToStateMessage(const pipeline::PlantSample& sample, int64_t utime) {
  const plant::PlantOutput& o = sample.output;
  odonata::plant_state_t m{};
  m.utime = utime;
  m.seq = sample.seq;
  m.command_seq = sample.command_seq;
  m.t_s = o.time_s;
  for (int i = 0; i < 3; ++i) {
    m.velocity_mps[i] = o.velocity_body_mps(i);
    m.rate_radps[i] = o.rate_body_radps(i);
    m.position_m[i] = o.position_m(i);
  }
  m.attitude_rad[0] = o.roll_rad;
  m.attitude_rad[1] = o.pitch_rad;
  m.attitude_rad[2] = o.yaw_rad;
  for (int w = 0; w < plant::kWingCount; ++w) {
    m.fx_n[w] = o.force_x_n(w);
    m.fz_n[w] = o.force_z_n(w);
  }
  m.status = StatusCode(sample.status);
  return m;
}

plant::PlantOutput ToPlantOutput(const odonata::plant_state_t& m) {
  plant::PlantOutput o;
  o.time_s = m.t_s;
  for (int i = 0; i < 3; ++i) {
    o.velocity_body_mps(i) = m.velocity_mps[i];
    o.rate_body_radps(i) = m.rate_radps[i];
    o.position_m(i) = m.position_m[i];
  }
  o.roll_rad = m.attitude_rad[0];
  o.pitch_rad = m.attitude_rad[1];
  o.yaw_rad = m.attitude_rad[2];
  for (int w = 0; w < plant::kWingCount; ++w) {
    o.force_x_n(w) = m.fx_n[w];
    o.force_z_n(w) = m.fz_n[w];
  }
  o.on_ground = m.status == odonata::plant_state_t::STATUS_ON_GROUND;
  return o;
}

std::optional<double> StateField(const odonata::plant_state_t& m, const std::string& name) {
  if (const auto i = plant::StateSignalIndex(name))
    return plant::StateSignalValues(ToPlantOutput(m))[*i];
  if (name == "t_s") return m.t_s;
  return std::nullopt;
}

bool AllFinite(const odonata::plant_state_t& m) {
  return std::isfinite(m.t_s) && FiniteValues(m.velocity_mps, 3) && FiniteValues(m.rate_radps, 3) &&
         FiniteValues(m.attitude_rad, 3) && FiniteValues(m.position_m, 3) &&
         FiniteValues(m.fx_n, 4) && FiniteValues(m.fz_n, 4);
}

}  // namespace odonata::messages

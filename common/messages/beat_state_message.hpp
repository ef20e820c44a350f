#pragma once
// beat_state_t ⇄ the plant's beat averages and the command its wings applied, and its named
// fields: the beat averages (plant::BeatSignalNames()) and the applied-command channels
// (vehicle::AppliedChannelNames()).

#include <cstdint>
#include <optional>
#include <string>

#include "odonata/beat_state_t.hpp"
#include "pipeline/plant_session.hpp"
#include "pipeline/vehicle_setup.hpp"

namespace odonata::messages {

/// Beat state `sample.seq`: the averages up to t_seq and the command applied over the sample
/// before it, read through `setup`'s trim into the applied-command channels; stamped `utime`.
odonata::beat_state_t ToBeatStateMessage(const pipeline::PlantSample& sample,
                                         const pipeline::VehicleSetup& setup, int64_t utime);

/// Which beat state holds a beat-state signal of sample k, as an offset from k: 0 for the beat
/// averages (beat state k, up to t_k, like state k), 1 for the applied-command channels (beat
/// state k + 1 carries the command applied over [t_k, t_k+1), which belongs with sample k's
/// command, as in odonata-sim's row k). nullopt when `name` is neither.
std::optional<int> BeatStateOffset(const std::string& name);

/// The value of a named beat average or applied channel (or "t_s", "window_s"); nullopt when
/// the name is unknown.
std::optional<double> BeatStateField(const odonata::beat_state_t& msg, const std::string& name);

/// True when every numeric field is finite (NaN or Inf ⇒ the message is dropped).
bool AllFinite(const odonata::beat_state_t& msg);

}  // namespace odonata::messages

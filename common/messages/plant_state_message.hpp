#pragma once
// plant_state_t ⇄ the plant's output, and its named fields (plant/output_signals.hpp).

#include <cstdint>
#include <optional>
#include <string>

#include "odonata/plant_state_t.hpp"
#include "pipeline/plant_session.hpp"
#include "plant/dimav_plant.hpp"

namespace odonata::messages {

/// State `sample.seq`, stamped `utime`.
odonata::plant_state_t ToStateMessage(const pipeline::PlantSample& sample, int64_t utime);

/// The output the message carries (beat averages left at zero: they travel in beat_state_t).
plant::PlantOutput ToPlantOutput(const odonata::plant_state_t& msg);

/// The value of a named output (plant::StateSignalNames()) or "t_s"; nullopt when the name is
/// unknown.
std::optional<double> StateField(const odonata::plant_state_t& msg, const std::string& name);

/// True when every numeric field is finite (NaN or Inf ⇒ the message is dropped).
bool AllFinite(const odonata::plant_state_t& msg);

}  // namespace odonata::messages

#pragma once
// NarxModel ⇄ model_snapshot_t: a model travels the bus as typed arrays (readable in lcm-spy),
// converted directly from and to its state (sysid/narx_model_state.hpp) and rebuilt through
// NarxModel::FromState, the same check a model file passes.

#include "odonata/model_snapshot_t.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::model_messages {

odonata::model_snapshot_t EncodeSnapshot(const sysid::NarxModel& model);
/// @throws std::runtime_error when the snapshot does not describe a valid model.
sysid::NarxModel DecodeSnapshot(const odonata::model_snapshot_t& msg);

}  // namespace odonata::model_messages

#pragma once
// NarxModel ⇄ model_snapshot_t: a model travels the bus as typed arrays (readable in lcm-spy)
// and is rebuilt through NarxModel::FromJson, so the same validation applies to both paths.

#include "odonata/model_snapshot_t.hpp"
#include "sysid/narx_model.hpp"

namespace odonata::model_messages {

odonata::model_snapshot_t EncodeSnapshot(const sysid::NarxModel& model);
/// @throws std::runtime_error when the snapshot does not describe a valid model.
sysid::NarxModel DecodeSnapshot(const odonata::model_snapshot_t& msg);

}  // namespace odonata::model_messages

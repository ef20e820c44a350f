#pragma once
// Checks an encoded message's array counts before lcm-gen's decode() sees them. LCM 1.3.1's
// generated decode() resizes each std::vector to the count the message claims before it checks
// that the bytes are there: a 100-byte packet claiming 2^31 strings makes it allocate ~64 GB
// (std::bad_alloc at best, an OOM kill or a sanitizer abort at worst). Walking the wire format
// first bounds every allocation by the packet's own size.
//
// There is one overload per type on the project's channels and deliberately no generic
// fallback: a new type must say how its arrays are laid out, or SafeDecode does not compile.

#include <cstdint>

#include "odonata/accuracy_t.hpp"
#include "odonata/ack_t.hpp"
#include "odonata/beat_state_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/prediction_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace odonata::bus {

/// True when the `size` bytes at `data` hold a message whose every string length and array count
/// is non-negative and fits in the bytes that remain (fingerprint included, top level).
/// The pointer argument only selects the type.
bool CountsFit(const odonata::wing_command_t*, const void* data, int64_t size);
bool CountsFit(const odonata::plant_state_t*, const void* data, int64_t size);
bool CountsFit(const odonata::beat_state_t*, const void* data, int64_t size);
bool CountsFit(const odonata::prediction_t*, const void* data, int64_t size);
bool CountsFit(const odonata::accuracy_t*, const void* data, int64_t size);
bool CountsFit(const odonata::model_snapshot_t*, const void* data, int64_t size);
bool CountsFit(const odonata::heartbeat_t*, const void* data, int64_t size);
bool CountsFit(const odonata::control_t*, const void* data, int64_t size);
bool CountsFit(const odonata::ack_t*, const void* data, int64_t size);

}  // namespace odonata::bus

#pragma once
// Decoding that never throws: lcm-gen's decode() resizes vectors to whatever count a corrupt
// message claims before it notices the buffer is too short; CountsFit (bus/wire_bounds.hpp,
// generated from the .lcm files by lcmtypes/gen_wire_bounds.py) rejects such a message before
// any allocation, and the catch stays as a second fence.

#include <cstdint>

#include "bus/wire_bounds.hpp"

namespace odonata::bus {

/// True when `data` holds a valid Msg (fingerprint, sizes and counts all consistent).
template <class Msg>
bool SafeDecode(Msg* msg, const void* data, int64_t size) {
  // A typed null selects CountsFit's overload: passing `msg`, an object not yet decoded, made
  // GCC 12 at -O2 warn that it may be read uninitialised (it is not read).
  if (size < 0 || size > INT32_MAX || !CountsFit(static_cast<const Msg*>(nullptr), data, size))
    return false;
  try {
    return msg->decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (...) {
    return false;
  }
}

}  // namespace odonata::bus

#pragma once
// Decoding that never throws: lcm-gen's decode() resizes vectors to whatever count a corrupt
// message claims (std::bad_alloc / length_error) before it notices the buffer is too short.

#include <cstdint>

namespace odonata::bus {

/// True when `data` holds a valid Msg (fingerprint, sizes and counts all consistent).
template <class Msg>
bool SafeDecode(Msg* msg, const void* data, int64_t size) {
  if (size < 0 || size > INT32_MAX) return false;
  try {
    return msg->decode(data, 0, static_cast<int>(size)) >= 0;
  } catch (...) {
    return false;
  }
}

}  // namespace odonata::bus

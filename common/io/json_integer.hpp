#pragma once
// Whole numbers read from JSON files and messages: nlohmann's get<int>() converts a fraction or
// 2e110 with a plain cast (undefined behaviour beyond the type's range) and wraps 4294967297 to
// 1. A count, lag or seq from outside goes through here instead.

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace odonata::io {

/// `v` as Int. @throws std::runtime_error naming `what` unless `v` is a whole JSON number within
/// Int's range.
template <class Int>
Int JsonInteger(const nlohmann::json& v, const std::string& what) {
  static_assert(std::numeric_limits<Int>::is_integer && std::numeric_limits<Int>::is_signed);
  if (!v.is_number_integer()) {
    throw std::runtime_error("\"" + what + "\" must be a whole number, not " + v.dump());
  }
  const bool fits =
      v.is_number_unsigned()
          ? v.get<uint64_t>() <= static_cast<uint64_t>(std::numeric_limits<Int>::max())
          : v.get<int64_t>() >= std::numeric_limits<Int>::min() &&
                v.get<int64_t>() <= std::numeric_limits<Int>::max();
  if (!fits) throw std::runtime_error("\"" + what + "\" is out of range: " + v.dump());
  return static_cast<Int>(v.get<int64_t>());
}

/// The same for an optional key: `fallback` when `j` has no `key`.
template <class Int>
Int JsonInteger(const nlohmann::json& j, const std::string& key, Int fallback) {
  return j.contains(key) ? JsonInteger<Int>(j.at(key), key) : fallback;
}

}  // namespace odonata::io

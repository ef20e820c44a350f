#pragma once
// A double as JSON: JSON has no NaN or infinity, so a value that is not finite (a diverged
// score, a gain with a pole at 1, an unbounded limit) is written as null.

#include <cmath>

#include <nlohmann/json.hpp>

namespace odonata::io {

inline nlohmann::json FiniteOrNull(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

}  // namespace odonata::io

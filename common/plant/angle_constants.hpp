#pragma once

namespace odonata::plant {
// One definition for the plant's sources and tests: C++17 has no std::numbers, and the unity
// build compiles several sources as one translation unit, where file-local copies would clash.
inline constexpr double kPi = 3.14159265358979323846;
inline constexpr double kTwoPi = 6.28318530717958647692;
inline constexpr double kRadPerDeg = kPi / 180.0;
inline constexpr double kDegPerRad = 180.0 / kPi;
}  // namespace odonata::plant

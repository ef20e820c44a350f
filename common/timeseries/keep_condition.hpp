#pragma once
// A condition on one signal that keeps the samples where it holds: "vehicle_land_detected.landed
// == 0" keeps a PX4 flight's airborne part, "thrust > 0.2" the part with the motors spinning.
// Samples where it does not hold are cut out as gaps are, so the data splits into segments there.

#include <optional>
#include <string>

namespace odonata::timeseries {

struct KeepCondition {
  enum class Op { kLess, kLessEqual, kGreater, kGreaterEqual, kEqual, kNotEqual };
  std::string signal;
  Op op = Op::kEqual;
  double value = 0.0;

  /// Whether `v` meets it; a NaN (no value yet) never does.
  bool Holds(double v) const;
  /// As written: "signal<op>value".
  std::string ToString() const;
};

/// "SIGNAL OP VALUE" with OP one of < <= > >= == != (spaces optional; the signal may hold '[',
/// ']', '.', '/').
/// @throws std::invalid_argument saying what a condition looks like.
KeepCondition ParseKeepCondition(const std::string& text);

/// PX4's airborne part: vehicle_land_detected.landed == 0.
KeepCondition Px4Airborne();

}  // namespace odonata::timeseries

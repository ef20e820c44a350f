#include "timeseries/keep_condition.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <utility>

namespace odonata::timeseries {
namespace {

constexpr std::pair<const char*, KeepCondition::Op> kOps[] = {
    {"<=", KeepCondition::Op::kLessEqual}, {">=", KeepCondition::Op::kGreaterEqual},
    {"==", KeepCondition::Op::kEqual},     {"!=", KeepCondition::Op::kNotEqual},
    {"<", KeepCondition::Op::kLess},       {">", KeepCondition::Op::kGreater}};

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? "" : s.substr(b, e - b + 1);
}

}  // namespace

bool KeepCondition::Holds(double v) const {
  if (std::isnan(v)) return false;
  switch (op) {
    case Op::kLess:
      return v < value;
    case Op::kLessEqual:
      return v <= value;
    case Op::kGreater:
      return v > value;
    case Op::kGreaterEqual:
      return v >= value;
    case Op::kEqual:
      return v == value;
    case Op::kNotEqual:
      return v != value;
  }
  return false;
}

std::string KeepCondition::ToString() const {
  for (const auto& [text, o] : kOps)
    if (o == op) {
      char v[32];
      std::snprintf(v, sizeof v, "%g", value);
      return signal + text + v;
    }
  return signal;
}

KeepCondition ParseKeepCondition(const std::string& text) {
  const std::string usage =
      "a condition is SIGNAL OP VALUE with OP one of < <= > >= == != "
      "(e.g. 'vehicle_land_detected.landed==0'), not '" +
      text + "'";
  // The operator is the first one found scanning left to right (the two-character ones first at
  // each position: "<=" is not "<").
  for (std::size_t i = 0; i < text.size(); ++i)
    for (const auto& [op_text, op] : kOps) {
      const std::string o = op_text;
      if (text.compare(i, o.size(), o) != 0) continue;
      KeepCondition c;
      c.signal = Trim(text.substr(0, i));
      c.op = op;
      const std::string value = Trim(text.substr(i + o.size()));
      char* end = nullptr;
      c.value = std::strtod(value.c_str(), &end);
      if (c.signal.empty() || value.empty() || *end != '\0' || !std::isfinite(c.value))
        throw std::invalid_argument(usage);
      return c;
    }
  throw std::invalid_argument(usage);
}

KeepCondition Px4Airborne() {
  return KeepCondition{"vehicle_land_detected.landed", KeepCondition::Op::kEqual, 0.0};
}

}  // namespace odonata::timeseries

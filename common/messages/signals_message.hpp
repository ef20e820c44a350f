#pragma once
// Any vehicle's samples by name (signals_t, docs/lcm.md §14) ⇄ values: the one place that reads
// a signal out of the message and says what is wrong with one.

#include <optional>
#include <string>

#include "odonata/signals_t.hpp"

namespace odonata::messages {

/// What is wrong with `msg` (a count that disagrees with its arrays, an empty or repeated name),
/// empty when nothing is. Values are not judged here: a NaN in a signal nobody reads is no harm.
std::string SignalsProblems(const odonata::signals_t& msg);

/// The value of signal `name`, or nothing when the message has no such signal.
std::optional<double> SignalValue(const odonata::signals_t& msg, const std::string& name);

}  // namespace odonata::messages

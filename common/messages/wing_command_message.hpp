#pragma once
// wing_command_t ⇄ the vehicle's command matrix, and its named fields (the names of
// experiments/sample_columns.hpp).

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "odonata/wing_command_t.hpp"
#include "pipeline/command_schedule.hpp"
#include "plant/wing_command.hpp"

namespace odonata::messages {

plant::CommandMatrix ToCommandMatrix(const odonata::wing_command_t& msg);

/// Command k of `schedule` with its excitation values, stamped `utime`.
/// @pre k < schedule.size().
odonata::wing_command_t ToCommandMessage(const pipeline::CommandSchedule& schedule, std::size_t k,
                                         int64_t utime);

/// The value of a named command ("w1_beta_rad" …), excitation or "t_s"; nullopt when the name is
/// unknown.
std::optional<double> CommandField(const odonata::wing_command_t& msg, const std::string& name);

/// True when every numeric field is finite (NaN or Inf ⇒ the message is dropped).
bool AllFinite(const odonata::wing_command_t& msg);

/// Problems of the variable-length arrays (count fields disagreeing with array sizes), empty
/// when fine: encode() trusts the counts, so a bad message must never be republished.
std::string CountProblems(const odonata::wing_command_t& msg);

}  // namespace odonata::messages

#pragma once
// Which operator commands a service obeys: "is this for me" and "may this sender do that", in one
// place for every service.

#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "odonata/control_t.hpp"

namespace odonata::bus {

/// Senders whose gated commands (IsDestructive) are obeyed when a service is given none
/// (--control-from):
/// the operator's tool and the generator, which resets the plant before each run.
const std::vector<std::string>& DefaultControlSenders();

/// True when `msg` is for this process: no target (every service), its instance or service name.
bool AddressedTo(const odonata::control_t& msg, const std::string& instance,
                 const std::string& service);

/// True when `msg` names this process (its instance or service name), not only "everyone": a
/// command the process has no use for is then answered as rejected, where a broadcast one is
/// left to the services it is for.
bool AddressedByName(const odonata::control_t& msg, const std::string& instance,
                     const std::string& service);

/// The operator's names of the commands ("set-entropy-threshold" → SET_ENTROPY_THRESHOLD), the
/// one table odonata-control parses and services word their replies with.
const std::map<std::string, int8_t>& ControlCommands();
/// The operator's name of `command`, or "command N" for an unknown one.
std::string ControlCommandName(int8_t command);

/// RESET, SHUTDOWN, FREEZE, RESUME and SAVE_MODEL: they throw away a model, stop a service, end or
/// restart learning mid-run, or write a file — what a forged message must not do (issue 24).
bool IsDestructive(int8_t command);

/// Empty when a process may obey `msg`, else why not (a destructive command from a sender not in
/// `allowed`).
std::string ControlRefusal(const odonata::control_t& msg, const std::vector<std::string>& allowed);

}  // namespace odonata::bus

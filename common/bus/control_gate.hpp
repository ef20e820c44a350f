#pragma once
// Which operator commands a service obeys: "is this for me" and "may this sender do that", in one
// place for every service.

#include <cstdint>
#include <string>
#include <vector>

#include "odonata/control_t.hpp"

namespace odonata::bus {

/// Senders whose RESET and SHUTDOWN are obeyed when a service is given none (--control-from):
/// the operator's tool and the generator, which resets the plant before each run.
const std::vector<std::string>& DefaultControlSenders();

/// True when `msg` is for this process: no target (every service), its instance or service name.
bool AddressedTo(const odonata::control_t& msg, const std::string& instance,
                 const std::string& service);

/// RESET and SHUTDOWN: they throw away a model or stop a service.
bool IsDestructive(int8_t command);

/// Empty when a process may obey `msg`, else why not (a destructive command from a sender not in
/// `allowed`).
std::string ControlRefusal(const odonata::control_t& msg, const std::vector<std::string>& allowed);

}  // namespace odonata::bus

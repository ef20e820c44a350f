#include "bus/control_gate.hpp"

#include <algorithm>

namespace odonata::bus {

const std::vector<std::string>& DefaultControlSenders() {
  static const std::vector<std::string> senders{"odonata-control", "odonata-signal"};
  return senders;
}

bool AddressedTo(const odonata::control_t& msg, const std::string& instance,
                 const std::string& service) {
  return msg.target.empty() || msg.target == instance || msg.target == service;
}

bool IsDestructive(int8_t command) {
  return command == odonata::control_t::RESET || command == odonata::control_t::SHUTDOWN;
}

std::string ControlRefusal(const odonata::control_t& msg, const std::vector<std::string>& allowed) {
  if (!IsDestructive(msg.command)) return "";
  if (std::find(allowed.begin(), allowed.end(), msg.sender) != allowed.end()) return "";
  return std::string(msg.command == odonata::control_t::RESET ? "reset" : "shutdown") +
         " from sender '" + msg.sender +
         "', which is not among the allowed senders (--control-from)";
}

}  // namespace odonata::bus

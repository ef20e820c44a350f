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

bool AddressedByName(const odonata::control_t& msg, const std::string& instance,
                     const std::string& service) {
  return !msg.target.empty() && (msg.target == instance || msg.target == service);
}

const std::map<std::string, int8_t>& ControlCommands() {
  static const std::map<std::string, int8_t> commands = {
      {"reset", odonata::control_t::RESET},
      {"freeze", odonata::control_t::FREEZE},
      {"resume", odonata::control_t::RESUME},
      {"set-entropy-threshold", odonata::control_t::SET_ENTROPY_THRESHOLD},
      {"set-forgetting", odonata::control_t::SET_FORGETTING},
      {"save-model", odonata::control_t::SAVE_MODEL},
      {"publish-snapshot", odonata::control_t::PUBLISH_SNAPSHOT},
      {"shutdown", odonata::control_t::SHUTDOWN},
      {"get", odonata::control_t::GET}};
  return commands;
}

std::string ControlCommandName(int8_t command) {
  for (const auto& [name, code] : ControlCommands())
    if (code == command) return name;
  return "command " + std::to_string(command);
}

bool IsDestructive(int8_t command) {
  return command == odonata::control_t::RESET || command == odonata::control_t::SHUTDOWN ||
         command == odonata::control_t::FREEZE || command == odonata::control_t::RESUME ||
         command == odonata::control_t::SAVE_MODEL;
}

std::string ControlRefusal(const odonata::control_t& msg, const std::vector<std::string>& allowed) {
  if (!IsDestructive(msg.command)) return "";
  if (std::find(allowed.begin(), allowed.end(), msg.sender) != allowed.end()) return "";
  return ControlCommandName(msg.command) + " from sender '" + msg.sender +
         "', which is not among the allowed senders (--control-from)";
}

}  // namespace odonata::bus

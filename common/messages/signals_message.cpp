#include "messages/signals_message.hpp"

#include <set>

namespace odonata::messages {

std::string SignalsProblems(const odonata::signals_t& msg) {
  if (msg.num_signals < 0 || static_cast<std::size_t>(msg.num_signals) != msg.names.size() ||
      msg.names.size() != msg.values.size())
    return "signals: num_signals " + std::to_string(msg.num_signals) + " disagrees with " +
           std::to_string(msg.names.size()) + " names and " + std::to_string(msg.values.size()) +
           " values";
  std::set<std::string> seen;
  for (const auto& n : msg.names) {
    if (n.empty()) return "signals: an empty signal name";
    if (!seen.insert(n).second) return "signals: '" + n + "' twice";
  }
  return "";
}

std::optional<double> SignalValue(const odonata::signals_t& msg, const std::string& name) {
  // A handful of signals: a linear scan beats building a map per message.
  for (std::size_t i = 0; i < msg.names.size() && i < msg.values.size(); ++i)
    if (msg.names[i] == name) return msg.values[i];
  return std::nullopt;
}

}  // namespace odonata::messages

#include "bus/channel_config.hpp"

#include <algorithm>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::bus {

const std::vector<std::pair<const char*, std::string ChannelConfig::*>>& ChannelConfig::Keys() {
  static const std::vector<std::pair<const char*, std::string ChannelConfig::*>> keys = {
      {"command", &ChannelConfig::command},
      {"state", &ChannelConfig::state},
      {"beat_state", &ChannelConfig::beat_state},
      {"prediction", &ChannelConfig::prediction},
      {"model", &ChannelConfig::model},
      {"accuracy", &ChannelConfig::accuracy},
      {"heartbeat", &ChannelConfig::heartbeat},
      {"control", &ChannelConfig::control},
      {"control_reply", &ChannelConfig::control_reply},
      {"ack", &ChannelConfig::ack},
      {"signals", &ChannelConfig::signals},
      {"signals_ack", &ChannelConfig::signals_ack}};
  return keys;
}

void ChannelConfig::ApplySuffix(const std::string& suffix) {
  if (suffix.empty()) return;
  for (const auto& [key, member] : Keys()) this->*member += "_" + suffix;
}

void ChannelConfig::Override(const nlohmann::json& j) {
  for (const auto& [key, value] : j.items()) {
    const auto& keys = Keys();
    const auto it = std::find_if(keys.begin(), keys.end(),
                                 [&key = key](const auto& k) { return key == k.first; });
    if (it == keys.end()) throw std::runtime_error("channels: unknown channel '" + key + "'");
    this->*(it->second) = value.get<std::string>();
  }
}

nlohmann::json ChannelConfig::ToJson(const ChannelConfig& defaults,
                                     const std::vector<std::string>& always) const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, member] : Keys())
    if (this->*member != defaults.*member ||
        std::find(always.begin(), always.end(), key) != always.end())
      j[key] = this->*member;
  return j;
}

void ChannelConfig::Set(const std::string& assignment) {
  const auto eq = assignment.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == assignment.size())
    throw std::runtime_error("channel assignment '" + assignment + "' is not KEY=NAME");
  Override(nlohmann::json{{assignment.substr(0, eq), assignment.substr(eq + 1)}});
}

void ChannelConfig::Configure(const std::string& suffix,
                              const std::vector<std::string>& assignments) {
  ApplySuffix(suffix);
  for (const std::string& a : assignments) Set(a);
}

}  // namespace odonata::bus

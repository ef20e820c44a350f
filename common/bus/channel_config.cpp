#include "bus/channel_config.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::bus {

void ChannelConfig::ApplySuffix(const std::string& suffix) {
  if (suffix.empty()) return;
  for (std::string* s : {&command, &state, &beat_state, &prediction, &model, &accuracy, &heartbeat,
                         &control, &control_reply, &ack, &signals, &signals_ack})
    *s += "_" + suffix;
}

void ChannelConfig::Override(const nlohmann::json& j) {
  for (const auto& [key, value] : j.items()) {
    std::string* target = key == "command"         ? &command
                          : key == "state"         ? &state
                          : key == "beat_state"    ? &beat_state
                          : key == "prediction"    ? &prediction
                          : key == "model"         ? &model
                          : key == "accuracy"      ? &accuracy
                          : key == "heartbeat"     ? &heartbeat
                          : key == "control"       ? &control
                          : key == "control_reply" ? &control_reply
                          : key == "ack"           ? &ack
                          : key == "signals"       ? &signals
                          : key == "signals_ack"   ? &signals_ack
                                                   : nullptr;
    if (!target) throw std::runtime_error("channels: unknown channel '" + key + "'");
    *target = value.get<std::string>();
  }
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

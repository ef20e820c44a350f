#include "bus/channel_config.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::bus {

void ChannelConfig::ApplySuffix(const std::string& suffix) {
  if (suffix.empty()) return;
  for (std::string* s : {&command, &state, &prediction, &model, &accuracy, &heartbeat, &control})
    *s += "_" + suffix;
}

void ChannelConfig::Override(const nlohmann::json& j) {
  for (const auto& [key, value] : j.items()) {
    std::string* target = key == "command"      ? &command
                          : key == "state"      ? &state
                          : key == "prediction" ? &prediction
                          : key == "model"      ? &model
                          : key == "accuracy"   ? &accuracy
                          : key == "heartbeat"  ? &heartbeat
                          : key == "control"    ? &control
                                                : nullptr;
    if (!target) throw std::runtime_error("channels: unknown channel '" + key + "'");
    *target = value.get<std::string>();
  }
}

}  // namespace odonata::bus

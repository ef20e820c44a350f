#pragma once
// Channel names: UPPER_SNAKE defaults, each overridable, with an optional suffix so two
// systems can share one bus (e.g. DIMAV_STATE_B).

#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json_fwd.hpp>

namespace odonata::bus {

struct ChannelConfig {
  std::string command = "DIMAV_COMMAND";
  std::string state = "DIMAV_STATE";
  std::string beat_state = "DIMAV_BEAT_STATE";  ///< beat averages and applied command (plant)
  std::string prediction = "ODONATA_PREDICTION";
  std::string model = "ODONATA_MODEL";
  std::string accuracy = "ODONATA_ACCURACY";
  std::string heartbeat = "ODONATA_HEARTBEAT";
  std::string control = "ODONATA_CONTROL";
  std::string control_reply = "ODONATA_CONTROL_REPLY";  ///< every service's answer to a command
  std::string ack = "ODONATA_ACK";          ///< lockstep receipts from consumers to the generator
  std::string signals = "VEHICLE_SIGNALS";  ///< any vehicle's samples by name (signals_t)
  /// Receipts of signals_t samples (ack_t, state_seq = the newest sample held), for a replay in
  /// lockstep (odonata-replay): apart from `ack`, so a plant's generator never mistakes them.
  std::string signals_ack = "VEHICLE_SIGNALS_ACK";

  /// Appends `_SUFFIX` to every name (no-op for an empty suffix).
  void ApplySuffix(const std::string& suffix);
  /// Overrides names from a JSON object {"command": "...", ...}; unknown keys are an error.
  /// @throws std::runtime_error naming the unknown key.
  void Override(const nlohmann::json& j);
  /// Renames one channel from a command-line assignment "KEY=NAME" (KEY as in Override).
  /// @throws std::runtime_error for a malformed assignment or an unknown key.
  void Set(const std::string& assignment);
  /// Renames from several assignments, after the suffix: an explicit name is taken as given.
  void Configure(const std::string& suffix, const std::vector<std::string>& assignments);
  /// The channels whose names differ from `defaults`, and those named in `always`, as the JSON
  /// Override reads.
  nlohmann::json ToJson(const ChannelConfig& defaults,
                        const std::vector<std::string>& always = {}) const;

 private:
  /// Every channel by its key: the one table of names that Override, Set and ToJson read.
  static const std::vector<std::pair<const char*, std::string ChannelConfig::*>>& Keys();
};

}  // namespace odonata::bus

#pragma once
// --channel-suffix, --channel KEY=NAME and --key, the same on every service.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/channel_config.hpp"

namespace odonata::cli {

struct ChannelOptions {
  std::string suffix;
  std::vector<std::string> names;  ///< KEY=NAME assignments
  std::string key_path;            ///< --key: the bus's shared key (bus::BusOptions::key_path)

  /// Suffix first, then the explicit names (taken as given).
  /// @throws std::runtime_error for a malformed assignment or an unknown key.
  void ApplyTo(bus::ChannelConfig* channels) const { channels->Configure(suffix, names); }
};

/// Adds both options to `app` (a program or a subcommand).
inline void AddChannelOptions(CLI::App* app, ChannelOptions* options) {
  app->add_option("--channel-suffix", options->suffix, "append _SUFFIX to every channel name");
  app->add_option("--channel", options->names,
                  "rename one channel, KEY=NAME with KEY one of command, state, beat_state, "
                  "prediction, model, accuracy, heartbeat, control, control_reply, ack, "
                  "signals, signals_ack (repeatable; applied after --channel-suffix)");
  app->add_option("--key", options->key_path,
                  "shared key file (64 hex digits, readable by its owner only): sign every "
                  "message this program publishes and refuse every one it receives that is not "
                  "signed with this key or is not new (docs/lcm.md §15)");
}

}  // namespace odonata::cli

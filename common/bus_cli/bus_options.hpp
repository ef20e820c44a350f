#pragma once
// --lcm-url, --instance, the channel options, --key and (for a service that obeys operators)
// --control-from: the same on every program on the bus, and the one place they become the
// bus::BusOptions its BusNode is opened with.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/bus_node.hpp"
#include "bus_cli/channel_options.hpp"
#include "bus_cli/control_options.hpp"

namespace odonata::cli {

struct BusCliOptions {
  std::string lcm_url;
  std::string instance;  ///< empty: the service's name (BusNode's default)
  ChannelOptions channels;
  std::vector<std::string> control_senders = bus::DefaultControlSenders();

  /// The options a BusNode of `service` opens with. @throws std::runtime_error for a malformed
  /// --channel assignment (ChannelOptions::ApplyTo).
  bus::BusOptions ToBusOptions(const std::string& service) const {
    bus::BusOptions o;
    o.lcm_url = lcm_url;
    o.key_path = channels.key_path;
    o.service = service;
    o.instance = instance;
    channels.ApplyTo(&o.channels);
    o.control_senders = control_senders;
    return o;
  }
};

/// What --instance means for this program, and whether it obeys operator commands.
struct BusCliSpec {
  std::string instance_help = "instance name";
  bool control = true;  ///< add --control-from
};

/// Adds the options to `app` (a program or a subcommand); a non-empty `options->instance` is
/// the default --instance, shown in --help.
inline void AddBusOptions(CLI::App* app, BusCliOptions* options, const BusCliSpec& spec = {}) {
  app->add_option("--lcm-url", options->lcm_url,
                  "LCM URL (default: LCM_DEFAULT_URL or udpm ttl=0)");
  auto* instance = app->add_option("--instance", options->instance, spec.instance_help);
  if (!options->instance.empty()) instance->capture_default_str();
  AddChannelOptions(app, &options->channels);
  if (spec.control) AddControlOptions(app, &options->control_senders);
}

}  // namespace odonata::cli

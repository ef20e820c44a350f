#pragma once
// --control-from, the same on every service that obeys operator commands.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus/control_gate.hpp"

namespace odonata::cli {

/// Adds --control-from to `app`; `senders` starts as (and, unless the option is given, stays)
/// bus::DefaultControlSenders().
inline void AddControlOptions(CLI::App* app, std::vector<std::string>* senders) {
  *senders = bus::DefaultControlSenders();
  app->add_option("--control-from", *senders,
                  "sender names (odonata-control --instance) whose reset, shutdown, freeze, resume "
                  "and save-model are obeyed; others are refused and logged (repeatable; a name "
                  "is not a proof: against attackers, sign the bus with --key)")
      ->capture_default_str();
}

}  // namespace odonata::cli

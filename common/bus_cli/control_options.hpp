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
                  "sender names (odonata-control --instance) whose reset and shutdown are obeyed; "
                  "others are refused and logged (repeatable; LCM authenticates nothing, so this "
                  "guards against mistakes, not attackers)")
      ->capture_default_str();
}

}  // namespace odonata::cli

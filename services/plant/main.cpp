// odonata-plant: the DI-MAV simulator as a vehicle on the bus. Answers DIMAV_COMMAND with
// DIMAV_STATE (and, beside it, DIMAV_BEAT_STATE: beat averages and the command applied), stepping
// once per command (lockstep) or on a 100 Hz clock (real time), and obeys
// RESET and SHUTDOWN on ODONATA_CONTROL. Exit codes: 0 ok, 1 runtime error, 2 bad arguments.

#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "experiments/experiment_preset.hpp"
#include "plant_node.hpp"

int main(int argc, char** argv) {
  std::string mode = "lockstep", preset, config_path;
  CLI::App app{
      "odonata-plant: the DI-MAV plant as a process. State k is published before command k is "
      "applied; the answer to command k is state k+1 (command_seq k). Beside every state, "
      "DIMAV_BEAT_STATE (same seq) carries its wing-beat averages and the command applied over "
      "the preceding sample, hold included. Free-flight presets fly with the onboard attitude "
      "hold, as odonata-sim does."};
  app.add_option("--mode", mode, "lockstep (one step per command) or realtime (100 Hz clock)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  app.add_option("--preset", preset,
                 "start from this preset's initial condition (default: free flight at 50 m, no "
                 "hold); presets: " +
                     odonata::experiments::PresetNames());
  app.add_option("--config", config_path, "plant configuration JSON (default: built-in 40 g set)")
      ->check(CLI::ExistingFile);
  odonata::cli::BusCliOptions bus_options;
  odonata::cli::AddBusOptions(&app, &bus_options, {"instance name (default odonata-plant)"});
  // Any option can also come from a settings file (TOML/INI, option names as keys).
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  odonata::plant::PlantConfig config;
  try {
    config = config_path.empty() ? odonata::plant::DefaultPlantConfig()
                                 : odonata::plant::LoadPlantConfig(config_path);
    if (!preset.empty() && !odonata::experiments::FindPreset(preset)) {
      throw std::invalid_argument("unknown preset '" + preset +
                                  "'; known presets: " + odonata::experiments::PresetNames());
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-plant: error: %s\n", e.what());
    return 2;
  }
  try {
    odonata::bus::BusNode bus(bus_options.ToBusOptions(odonata::plant_service::kServiceName));
    odonata::plant_service::PlantNode node(bus, config,
                                           mode == "lockstep"
                                               ? odonata::pipeline::PlantSession::Mode::kLockstep
                                               : odonata::pipeline::PlantSession::Mode::kRealtime,
                                           preset);
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-plant: error: %s\n", e.what());
    return 1;
  }
}

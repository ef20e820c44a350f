// odonata-signal: sends an experiment's commands to odonata-plant over DIMAV_COMMAND, in lockstep
// (each command waits for the plant's answer, resending on timeout) or in real time (a clock).
// Exit codes (signal_node.hpp): 0 all commands sent (and answered, in lockstep), 1 no plant /
// runtime error, 2 bad arguments or input, 3 the plant diverged, 4 a lockstep consumer left,
// 5 stopped by a signal, 6 the plant restarted mid-run in real time, 7 a consumer refused (key).

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <string>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "experiments/experiment_preset.hpp"
#include "pipeline/command_schedule.hpp"
#include "plant/plant_config.hpp"
#include "sequence/lockstep_window.hpp"
#include "signal_node.hpp"

int main(int argc, char** argv) {
  std::string preset, phase = "train", commands_path, config_path, mode = "lockstep";
  std::uint64_t seed = 1;
  double duration_s = 0.0;
  odonata::signal_service::SignalOptions options;
  CLI::App app{
      "odonata-signal: sends a preset's (or a file's) wing commands to odonata-plant. Command k "
      "carries the 24 wing commands, the preset's excitation(s), t_s and its source."};
  app.footer(
      "Exit codes: 0 every command sent (and answered, in lockstep); 1 no plant, or a runtime "
      "error; 2 bad arguments or input; 3 the plant diverged; 4 a lockstep consumer left "
      "mid-run; 5 stopped by a signal before the last command; 6 the plant restarted mid-run "
      "(real time): the log holds the run in parts; 7 a lockstep consumer's messages are "
      "refused (no or another --key): the run could not be lossless for it.");
  auto* preset_opt = app.add_option("--preset", preset,
                                    "experiment preset: " + odonata::experiments::PresetNames());
  app.add_option("--phase", phase, "train, select or validate (with --preset)")
      ->check(CLI::IsMember(odonata::experiments::PhaseNames()));
  app.add_option("--seed", seed, "random seed (with --preset), as odonata-sim's");
  app.add_option("--duration", duration_s, "duration in s (default: the preset's or the file's)")
      ->check(CLI::PositiveNumber);
  auto* commands_opt =
      app.add_option("--commands", commands_path,
                     "command CSV: t_s, the 24 w{i}_* columns, optional u_* columns")
          ->check(CLI::ExistingFile);
  preset_opt->excludes(commands_opt);
  app.add_option("--config", config_path,
                 "plant configuration JSON the commands are built for (default: built-in 40 g)")
      ->check(CLI::ExistingFile);
  app.add_option("--mode", mode, "lockstep (paced by the answers) or realtime (a clock)")
      ->check(CLI::IsMember({"lockstep", "realtime"}));
  app.add_option("--rate-hz", options.rate_hz, "realtime: commands per second")
      ->check(CLI::PositiveNumber);
  app.add_option("--timeout-ms", options.timeout_ms, "lockstep: resend after this long")
      ->check(CLI::Range(1, 600000));
  app.add_option("--window", options.window,
                 "lockstep: commands in flight; the plant applies them in order, so every window "
                 "gives the same run, a larger one a faster one")
      ->capture_default_str()
      ->check(CLI::Range(1, odonata::pipeline::LockstepSequencer::kMaxWindow));
  app.add_flag("!--keep-going-without-refused", options.refused_consumers_fail,
               "lockstep with --key: when a consumer is heard whose messages are refused (no key, "
               "another key), go on without it and exit 7 at the end, instead of stopping at once "
               "(a forger's heartbeat looks the same)");
  app.add_option("--refit-wait", options.refit_wait_s,
                 "lockstep: seconds to wait for consumers that say they are landing a refit "
                 "before failing (default 600 with --key, 45 without: on a keyless bus anyone "
                 "can claim to be refitting)")
      ->check(CLI::Range(0.0, 1e6));
  app.add_option("--max-resends", options.max_resends,
                 "consecutive resends before giving up on the plant")
      ->check(CLI::Range(0, 1000000));
  app.add_flag("--reset-plant,!--no-reset-plant", options.reset_plant,
               "send RESET (with the preset) first and wait for a fresh state 0 (default on)");
  app.add_option("--plant", options.plant, "plant instance to reset and wait for");
  options.discover_s = odonata::pipeline::kLockstepDiscoverySeconds;
  app.add_option("--wait-for", options.wait_for,
                 "lockstep: a consumer instance whose receipt (ODONATA_ACK) of each state the "
                 "window waits for (repeatable)");
  app.add_option("--discover-consumers", options.discover_s,
                 "lockstep: seconds to listen for identifier and logger heartbeats before the "
                 "first command; each one heard is waited for too, so none loses a sample (0: "
                 "only --wait-for)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--hold-at", options.hold_at,
                 "lockstep, for tests: send no command from this seq on until SIGUSR1; stderr "
                 "says 'holding before command K' once every state up to K is confirmed, so a "
                 "fault injected then lands at a definite sample")
      ->check(CLI::PositiveNumber);
  odonata::cli::BusCliOptions bus_options;
  odonata::cli::AddBusOptions(&app, &bus_options,
                              {"instance name (default odonata-signal)", false});
  // Any option can also come from a settings file (TOML/INI, option names as keys).
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  if (preset.empty() == commands_path.empty()) {
    std::fprintf(stderr,
                 "odonata-signal: give exactly one of --preset or --commands (see --help)\n");
    return 2;
  }
  options.lockstep = mode == "lockstep";
  options.progress = isatty(STDERR_FILENO) == 1;
  odonata::pipeline::CommandSchedule schedule;
  try {
    const odonata::plant::PlantConfig config = config_path.empty()
                                                   ? odonata::plant::DefaultPlantConfig()
                                                   : odonata::plant::LoadPlantConfig(config_path);
    if (!preset.empty()) {
      const auto* p = odonata::experiments::FindPreset(preset);
      if (!p) {
        throw std::invalid_argument("unknown preset '" + preset +
                                    "'; known presets: " + odonata::experiments::PresetNames());
      }
      schedule = odonata::pipeline::PresetSchedule(*p, *odonata::experiments::ParsePhase(phase),
                                                   seed, duration_s, config);
    } else {
      schedule = odonata::pipeline::FileSchedule(commands_path, config, duration_s);
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-signal: error: %s\n", e.what());
    return 2;
  }
  try {
    odonata::bus::BusNode bus(bus_options.ToBusOptions(odonata::signal_service::kServiceName));
    odonata::signal_service::SignalNode node(bus, std::move(schedule), options);
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-signal: error: %s\n", e.what());
    return 1;
  }
}

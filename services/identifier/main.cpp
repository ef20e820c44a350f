// odonata-identifier: learns an entropy fuzzy model online from the plant's command, state and
// beat-state messages and publishes its predictions and model snapshots.

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "bus_cli/bus_options.hpp"
#include "cli/parse_command_line.hpp"
#include "identifier_node.hpp"
#include "model_export/fis_import.hpp"

int main(int argc, char** argv) {
  std::string config_path, model_path, save_path;
  bool print_config = false, check_config = false;
  double resume_wait_s = -1;
  CLI::App app{
      "Online entropy fuzzy identifier. Pairs DIMAV_COMMAND, DIMAV_STATE and (for beat averages "
      "*_avg and applied-command channels u_*_applied_rad) DIMAV_BEAT_STATE by sequence number, "
      "learns from every sample, publishes ODONATA_PREDICTION per sample and ODONATA_MODEL "
      "snapshots; obeys ODONATA_CONTROL (freeze, resume, reset, set H, save, snapshot)."};
  app.add_option("--config", config_path,
                 "configuration file (JSON; default: the roll loop printed by --print-config)");
  app.add_option("--model", model_path,
                 "start from this saved model (JSON), or from rules in a Sugeno .fis (Gaussian "
                 "inputs named as odonata-export names the regressor, linear or constant "
                 "outputs), instead of the bus snapshot")
      ->check(CLI::ExistingFile);
  app.add_option("--save-model", save_path, "write the model here on exit and on SAVE_MODEL");
  std::string models_dir;
  app.add_option("--models-dir", models_dir,
                 "where save-model with a file name writes (a plain name only; default: the "
                 "directory of --save-model; without either, named saves are refused)");
  odonata::cli::BusCliOptions bus_options;
  odonata::cli::AddBusOptions(&app, &bus_options, {"instance name (overrides the configuration)"});
  app.add_option("--resume-wait", resume_wait_s, "seconds to wait for a snapshot to resume from");
  app.add_flag("--print-config", print_config,
               "print an example configuration and exit; with --config, the whole configuration "
               "that file gives (every key, the defaults filled in), checked");
  app.add_flag("--check-config", check_config,
               "read --config (and --model), say what it identifies, and exit: 0 when it can be "
               "used as it is");
  // The same settings file as the other services (a board's launch, deploy/board/); the model
  // itself stays in the JSON of --config.
  app.set_config("--settings", "", "read options from this TOML/INI file");
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  if (print_config && config_path.empty()) {
    std::cout << odonata::identifier::ExampleIdentifierConfig();
    return 0;
  }
  try {
    auto config = config_path.empty() ? odonata::identifier::DefaultIdentifierConfig()
                                      : odonata::identifier::LoadIdentifierConfig(config_path);
    if (config_path.empty())
      std::fprintf(stderr, "[%s] no --config: identifying the roll loop (see --print-config)\n",
                   config.instance.c_str());
    if (!bus_options.instance.empty()) config.instance = bus_options.instance;
    if (resume_wait_s >= 0) config.resume_wait_s = resume_wait_s;
    bus_options.channels.ApplyTo(&config.channels);
    if (print_config) {  // with --config: what this identifier would run with, every key
      std::cout << odonata::identifier::IdentifierConfigToJson(config).dump(2) << "\n";
      return 0;
    }
    std::optional<odonata::sysid::NarxModel> initial;
    if (!model_path.empty()) {
      if (model_path.size() > 4 && model_path.compare(model_path.size() - 4, 4, ".fis") == 0) {
        // Rules in raw units (odonata-export's, or written by hand): unfolded into this
        // configuration's regressor and ranges (docs/model_export.md §6).
        odonata::sysid::NarxModel empty(config.spec, config.model);
        empty.SetScaling(odonata::sysid::ScalingFromRanges(config.spec, config.ranges));
        initial = odonata::model_export::LoadFis(model_path, empty);
      } else {
        initial = odonata::sysid::NarxModel::Load(model_path);
      }
    }
    if (check_config) {
      const auto& sp = config.spec;
      std::printf("%s: %s identifies", config.instance.c_str(),
                  config_path.empty() ? "the default configuration" : config_path.c_str());
      for (const auto& o : sp.outputs) std::printf(" %s", o.c_str());
      std::printf(" from");
      for (const auto& i : sp.inputs) std::printf(" %s", i.c_str());
      const std::string refits =
          !config.refit.enabled() ? "off"
          : config.refit.horizon >= 2
              ? "on, choosing " + std::to_string(config.refit.horizon) + " steps ahead"
              : "on, choosing in free run";
      std::printf(" (ny %d, nu %d, delay %d), %s consequents, H %.4g, kappa %.3g, refits %s%s\n",
                  sp.output_lags, sp.input_lags, sp.delay,
                  odonata::fuzzy::ToString(config.model.consequent), config.model.entropy.threshold,
                  config.model.entropy.kappa, refits.c_str(),
                  initial ? ", starting from the model given" : "");
      return 0;
    }
    // The configuration names the instance and the channels (--instance, --channel applied to
    // it above).
    odonata::bus::BusOptions opts = bus_options.ToBusOptions("odonata-identifier");
    opts.instance = config.instance;
    opts.channels = config.channels;
    if (models_dir.empty() && !save_path.empty()) {
      models_dir = std::filesystem::path(save_path).parent_path().string();
      if (models_dir.empty()) models_dir = ".";
    }
    odonata::bus::BusNode bus(opts);
    odonata::identifier::IdentifierNode node(bus, config, initial, save_path, models_dir);
    return bus.Run();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-identifier: error: %s\n", e.what());
    return 1;
  }
}

// odonata-sim: runs an experiment preset or a command file through the DI-MAV plant offline and
// writes a CSV for odonata-fit. Exit codes: 0 ok, 2 bad arguments/input/configuration, 3 the plant
// diverged with policy "stop" (the CSV holds the rows up to the divergence).

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <exception>
#include <string>
#include "cli/parse_command_line.hpp"

#include <nlohmann/json.hpp>

#include "experiments/experiment_preset.hpp"
#include "plant/plant_config.hpp"
#include "sim_runner.hpp"

namespace {

void ListPresets() {
  for (const odonata::experiments::ExperimentPreset& p : odonata::experiments::Presets()) {
    std::printf("%s: %s\n", p.name.c_str(), p.description.c_str());
    std::printf("  output %s, input", p.output_column.c_str());
    for (const std::string& in : p.input_columns) std::printf(" %s", in.c_str());
    std::printf(", ny %d nu %d delay %d, decimate %d, H %.3g (paper %s, %d MFs, %s)\n", p.ny, p.nu,
                p.delay, p.decimate, p.entropy_threshold, p.paper_entropy_text.c_str(),
                p.paper_mf_count, p.paper_accuracy_text.c_str());
    std::printf("  train %.0f s: %s\n  select %.0f s: %s\n  validate %.0f s: %s\n",
                p.train_duration_s, p.train_excitation.c_str(), p.select_duration_s,
                p.select_excitation.c_str(), p.validate_duration_s, p.validate_excitation.c_str());
  }
}

/// The presets as JSON, for scripts (deploy/odonata-run, the main job's report).
void ListPresetsJson() {
  nlohmann::json all = nlohmann::json::array();
  for (const odonata::experiments::ExperimentPreset& p : odonata::experiments::Presets()) {
    all.push_back({{"name", p.name},
                   {"description", p.description},
                   {"output", p.output_column},
                   {"inputs", p.input_columns},
                   {"ny", p.ny},
                   {"nu", p.nu},
                   {"delay", p.delay},
                   {"entropy_threshold", p.entropy_threshold},
                   {"paper_entropy", p.paper_entropy_text},
                   {"paper_mfs", p.paper_mf_count},
                   {"paper_accuracy", p.paper_accuracy_text},
                   {"train_duration_s", p.train_duration_s},
                   {"validate_duration_s", p.validate_duration_s},
                   {"select_duration_s", p.select_duration_s},
                   {"held_vehicle", p.held_vehicle},
                   {"decimate", p.decimate},
                   {"beyond_paper", p.beyond_paper},
                   {"damage_at_s", std::isfinite(p.validate_damage.at_s)
                                       ? nlohmann::json(p.validate_damage.at_s)
                                       : nlohmann::json(nullptr)},
                   {"clamped_body", p.clamped_body},
                   {"attitude_hold", p.attitude_hold},
                   {"train_excitation", p.train_excitation},
                   {"validate_excitation", p.validate_excitation},
                   {"select_excitation", p.select_excitation}});
  }
  std::printf("%s\n", all.dump(1).c_str());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"odonata-sim: simulate the DI-MAV flapping-wing plant and write a CSV"};
  std::string preset_name, phase_name = "train", config_path, commands_path, output_path;
  std::uint64_t seed = 1;
  double duration_s = 0.0;
  double altitude_m = 50.0;
  bool list = false, json = false;
  app.add_flag("--list-presets", list, "List the experiment presets and exit");
  app.add_flag("--json", json, "With --list-presets: print them as JSON");
  auto* preset_opt =
      app.add_option("--preset", preset_name, "Experiment preset (see --list-presets)");
  app.add_option("--phase", phase_name,
                 "train, select (for choices: H, widths, order) or validate (never for a "
                 "choice); with --preset")
      ->check(CLI::IsMember(odonata::experiments::PhaseNames()));
  app.add_option("--seed", seed, "Random seed (with --preset)");
  app.add_option("--duration", duration_s, "Duration in s (default: the preset's)")
      ->check(CLI::PositiveNumber);
  auto* commands_opt = app.add_option(
      "--commands", commands_path, "Command CSV: t_s and the 24 w{i}_* columns at the sample rate");
  app.add_option("--altitude", altitude_m, "Start height in m (with --commands)");
  app.add_option("--config", config_path, "Plant configuration JSON (default: built-in 40 g set)");
  app.add_option("--output", output_path, "Output CSV file");
  odonata::plant::ActuatorDamage damage;
  auto* damage_opt = app.add_option(
      "--damage-at", damage.at_s,
      "damage scenario: from this time (s) on, one wing delivers less than commanded (default: "
      "the preset's, none outside the damage presets' validation run)");
  app.add_option("--damage-wing", damage.wing,
                 "the damaged wing, 1…4, or 0 for all four (a sagging battery)")
      ->capture_default_str()
      ->needs(damage_opt);
  app.add_option("--damage-amplitude", damage.amplitude_scale,
                 "delivered stroke amplitude / commanded (0.7: 30 % lost)")
      ->capture_default_str()
      ->needs(damage_opt);
  app.add_option("--damage-frequency", damage.frequency_scale,
                 "delivered flapping frequency / commanded (a sagging battery)")
      ->capture_default_str()
      ->needs(damage_opt);
  int decimate = 0;
  app.add_option("--decimate", decimate,
                 "write one row per N samples: outputs (and their _avg) at the block's first "
                 "sample, inputs averaged over the block (N = 19 is about one wing beat at hover); "
                 "default: the preset's (see --list-presets), 1 with --commands")
      ->check(CLI::Range(1, 1000000));
  preset_opt->excludes(commands_opt);
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;
  if (list) {
    if (json) {
      ListPresetsJson();
      return 0;
    }
    ListPresets();
    return 0;
  }
  if (preset_name.empty() == commands_path.empty()) {
    std::fprintf(stderr, "odonata-sim: give exactly one of --preset or --commands (see --help)\n");
    return 2;
  }
  if (output_path.empty()) {
    std::fprintf(stderr, "odonata-sim: --output FILE.csv is required\n");
    return 2;
  }
  try {
    const odonata::plant::PlantConfig config = config_path.empty()
                                                   ? odonata::plant::DefaultPlantConfig()
                                                   : odonata::plant::LoadPlantConfig(config_path);
    odonata::experiments::ExperimentRun run;
    if (!preset_name.empty()) {
      const auto* preset = odonata::experiments::FindPreset(preset_name);
      if (!preset) {
        std::fprintf(stderr, "odonata-sim: unknown preset '%s'; known presets: %s\n",
                     preset_name.c_str(), odonata::experiments::PresetNames().c_str());
        return 2;
      }
      const auto phase = *odonata::experiments::ParsePhase(phase_name);
      run = odonata::experiments::BuildExperimentRun(*preset, phase, seed, duration_s, config);
      if (decimate == 0) decimate = preset->decimate;
    } else {
      run = odonata::sim::ReadCommandFile(commands_path, config, altitude_m);
      if (duration_s > 0.0) {
        const auto rows = static_cast<std::size_t>(duration_s / run.sample_period_s + 0.5);
        if (rows < run.commands.size()) run.commands.resize(rows);
      }
    }
    if (const std::string p = damage.Problems(); !p.empty()) {
      std::fprintf(stderr, "odonata-sim: %s\n", p.c_str());
      return 2;
    }
    if (damage_opt->count() > 0) run.damage = damage;
    if (decimate == 0) decimate = 1;
    const odonata::sim::SimResult result =
        odonata::sim::RunAndWrite(config, run, output_path, decimate);
    for (const std::string& m : result.messages)
      std::fprintf(stderr, "odonata-sim: %s\n", m.c_str());
    if (result.stopped) {
      std::fprintf(stderr, "odonata-sim: stopped after %zu rows; %s is truncated\n",
                   result.rows_written, output_path.c_str());
      return 3;
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "odonata-sim: %s\n", e.what());
    return 2;
  }
}

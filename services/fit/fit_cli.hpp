#pragma once
// odonata-fit's command line: the options, grouped as --help lists them (data, learner, refits,
// selection, outputs), and what they set in FitJobOptions. main.cpp only parses and runs.

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "cli/csv_format_options.hpp"
#include "fit/fit_job.hpp"

namespace odonata::fit {

/// What the command line holds besides FitJobOptions: values read as text or converted after
/// parsing, and the options whose presence says "given, not to be chosen".
struct FitCli {
  std::string consequent;
  std::string measure = "firing";
  std::string criterion = "auto";
  double learning_rate = 0;
  double tolerance_percent = 0;
  int simulation_steps = 30;
  std::vector<int> simulation_horizons{10, 40, 160, 640};
  bool json = false, rules = false, full_rules = false, no_ls = false, no_select = false;
  bool airborne = false;
  std::string keep_when, time_unit;
  std::string report_dir;  ///< --report: the page's directory
  cli::CsvFormatOptions csv_format;
  CLI::Option* threshold = nullptr;
  CLI::Option* epochs = nullptr;
  CLI::Option* sim_steps = nullptr;
  CLI::Option* kind = nullptr;
  CLI::Option* kappa = nullptr;
  CLI::Option* deviation_ridge = nullptr;
};

/// Adds every option to `app`, bound to `c` and `o` (which keep their defaults until parsed).
void AddFitOptions(CLI::App* app, FitCli& c, FitJobOptions* o);

/// After parsing: the text options converted, the given settings marked, the schedule built.
/// @throws std::runtime_error for a missing --train or --output.
void ApplyFitCli(const FitCli& c, FitJobOptions& o);

}  // namespace odonata::fit

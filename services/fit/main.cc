// odonata-fit: fit an entropy fuzzy NARX model offline on CSV files and report its accuracy.

#include <iostream>

#include <CLI/CLI.hpp>

#include "cli/parse_command_line.hpp"
#include "fit_job.hpp"
#include "progress_bar.hpp"

int main(int argc, char** argv) {
  odonata::fit::FitJobOptions o;
  std::string consequent = "singleton";
  std::string measure = "firing";
  std::string criterion = "one_step";
  double learning_rate = o.model.rates.centre;
  bool json = false, rules = false, no_ls = false;
  o.spec.output_lags = 1;
  o.spec.input_lags = 1;
  o.spec.delay = 1;

  CLI::App app{
      "Fits an entropy fuzzy model (series-parallel NARX) on CSV data: header row, one sample per "
      "row. Reports FIT/VAF/RMSE one-step and free-run, beside linear ARX and persistence."};
  app.add_option("--train", o.train_csv, "training CSV")->check(CLI::ExistingFile);
  app.add_option("--validate", o.validate_csv, "validation CSV (a different excitation)")
      ->check(CLI::ExistingFile);
  app.add_option("--output", o.output, "column to identify");
  app.add_option("--input", o.inputs, "input column (repeat for several)");
  app.add_option("--ny", o.spec.output_lags, "output lags n")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  app.add_option("--nu", o.spec.input_lags, "input lags m")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  app.add_option("--delay", o.spec.delay, "input delay: 1 predicts y(k+1) (eq. 7), 0 predicts y(k)")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1}));
  app.add_option("--entropy-threshold", o.model.entropy.threshold,
                 "H̄: a rule is created when max entropy ≤ H̄ (lower ⇒ fewer rules)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.531));
  app.add_option("--max-rules", o.model.entropy.max_rules, "hard cap on the rule count")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--epochs", o.train.epochs, "passes over the data (first grows rules, later tune)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
  app.add_option("--learning-rate", learning_rate,
                 "gradient rate for centres and widths (scaled units)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  app.add_option("--consequent", consequent,
                 "singleton (paper, readable) or linear (Takagi–Sugeno)")
      ->capture_default_str()
      ->check(CLI::IsMember({"singleton", "linear"}));
  app.add_option("--entropy-measure", measure, "firing (paper) or per_input")
      ->capture_default_str()
      ->check(CLI::IsMember({"firing", "per_input"}));
  app.add_option("--kappa", o.model.entropy.kappa, "new width = kappa · distance to nearest centre")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--sigma-min", o.model.entropy.sigma_min, "smallest width (scaled units)")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  app.add_option("--ridge", o.train.ridge, "least-squares ridge, relative to the mean diagonal")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--no-least-squares", no_ls,
               "skip the global least-squares consequent solve after each pass (pure online "
               "learning, as the online identifier does)");
  app.add_option("--seed", o.seed, "recorded in the report; the learning itself uses no randomness")
      ->capture_default_str();
  app.add_option("--save-model", o.save_model, "write the model as JSON");
  app.add_option("--load-model", o.load_model, "evaluate a saved model instead of training")
      ->check(CLI::ExistingFile);
  app.add_option("--ranges", o.ranges,
                 "JSON {signal: [min, max]}: fixes the scaling instead of deriving it from the "
                 "training data (what the online identifier uses)")
      ->check(CLI::ExistingFile);
  app.add_option("--save-ranges", o.save_ranges, "write the training data's signal ranges as JSON");
  app.add_flag("--rules", rules, "list the rules as sentences");
  app.add_flag("--json", json, "print one JSON object on stdout");
  app.add_flag("--sweep", o.sweep,
               "sweep H̄, print validation accuracy against rule count, and fit with the smallest "
               "model within --sweep-tolerance of the best");
  app.add_option("--sweep-thresholds", o.sweep_options.thresholds,
                 "H̄ values to sweep (default 12, log-spaced 0.001–0.45)")
      ->delimiter(',');
  app.add_option("--sweep-tolerance", o.sweep_options.tolerance_percent,
                 "FIT points below the best still acceptable")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app.add_option("--sweep-criterion", criterion, "score by one_step or free_run validation FIT")
      ->capture_default_str()
      ->check(CLI::IsMember({"one_step", "free_run"}));
  if (const auto code = odonata::cli::ParseCommandLine(app, argc, argv)) return *code;

  try {
    if (o.load_model.empty()) {
      if (o.train_csv.empty()) throw std::runtime_error("--train is required (or --load-model)");
      if (o.output.empty()) throw std::runtime_error("--output is required");
    }
    o.model.consequent = odonata::fuzzy::ConsequentKindFromString(consequent);
    o.model.entropy.measure = measure == "firing" ? odonata::fuzzy::EntropyMeasure::kFiring
                                                  : odonata::fuzzy::EntropyMeasure::kPerInput;
    o.model.rates.centre = learning_rate;
    o.model.rates.sigma = learning_rate;
    o.train.refine_least_squares = !no_ls;
    o.sweep_options.free_run_criterion = criterion == "free_run";
    o.progress = odonata::fit::StderrIsTerminal();
    const auto report = odonata::fit::RunFitJob(o);
    if (json) {
      std::cout << report.dump(1) << std::endl;
    } else {
      std::cout << odonata::fit::FormatReport(report, rules);
    }
  } catch (const std::exception& e) {
    std::cerr << "odonata-fit: error: " << e.what() << std::endl;
    return 1;
  }
  return 0;
}

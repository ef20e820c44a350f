#include "fit_cli.hpp"

#include <string>
#include <vector>

namespace odonata::fit {
namespace {

// Which part of each file is read: a window, and a condition such as "airborne".
void AddWindowOptions(CLI::App* app, FitCli& c, FitJobOptions* o) {
  app->add_option("--from", o->from_s,
                  "read each file from this time on, in seconds on its own time axis (a ULog: "
                  "since its start; a CSV: its --time column, or row / --rate)");
  app->add_option("--to", o->to_s, "read each file up to this time (seconds, as --from)");
  app->add_flag("--airborne", c.airborne,
                "keep only a PX4 log's airborne part (vehicle_land_detected.landed == 0); "
                "--keep-when names another condition");
  app->add_option("--keep-when", c.keep_when,
                  "keep only the samples where this holds: SIGNAL OP VALUE, OP one of < <= > >= "
                  "== != (e.g. 'vehicle_thrust_setpoint.xyz[2]<-0.1'); the signal is held, "
                  "never interpolated");
  app->add_option("--time-unit", c.time_unit,
                  "unit of the --time column: s, ms or us (default: from its name, *_ms or "
                  "*_us, else s)")
      ->check(CLI::IsMember({"s", "ms", "us"}));
}

// The data: files, signals, lags and how a real log is read.
void AddDataOptions(CLI::App* app, FitJobOptions* o) {
  app->add_option("--train", o->train_csv,
                  "training CSV, or a PX4 ULog (.ulg: --output and --input name its signals "
                  "topic.field, topic.field[i], topic/1.field; resampled onto --rate)")
      ->check(CLI::ExistingFile);
  app->add_option("--validate", o->validate_csv, "validation CSV (a different excitation)")
      ->check(CLI::ExistingFile);
  app->add_option(
      "--output", o->outputs,
      "column to identify (repeat for several: one model each over a shared regressor)");
  app->add_option("--time", o->time_column,
                  "time column in seconds: samples are resampled onto a fixed rate (--rate) by "
                  "linear interpolation");
  app->add_option("--rate", o->rate_hz,
                  "the rate in Hz: with --time or a ULog, the grid's (default: the slowest chosen "
                  "signal's median rate, which every signal fills); without, the rows' (time "
                  "constants are then in seconds)")
      ->check(CLI::Range(1e-6, 1e7));
  app->add_option("--max-gap", o->max_gap,
                  "missing samples (empty or NaN cells, or time gaps) bridged by linear "
                  "interpolation up to this many in a row; a longer gap splits the data into "
                  "segments")
      ->capture_default_str()
      ->check(CLI::Range(0, 1000000));
  app->add_option("--input", o->inputs, "input column (repeat for several)");
  app->add_option("--ny", o->spec.output_lags, "output lags n")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  app->add_option("--nu", o->spec.input_lags, "input lags m")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  app->add_option("--delay", o->spec.delay,
                  "input delay: 1 predicts y(k+1) (eq. 7), 0 predicts y(k)")
      ->capture_default_str()
      ->check(CLI::IsMember({0, 1}));
}

// The learner's settings (chosen on a hold-out when not given) and its training.
void AddLearnerOptions(CLI::App* app, FitCli& c, FitJobOptions* o) {
  c.threshold = app->add_option(
      "--entropy-threshold", o->model.entropy.threshold,
      "H̄ in [0, 0.5307]: a rule is created when max entropy ≤ H̄ (lower ⇒ fewer rules); "
      "chosen when not given");
  c.threshold->capture_default_str();
  app->add_option("--max-rules", o->model.entropy.max_rules, "hard cap on the rule count")
      ->capture_default_str();
  c.epochs = app->add_option("--epochs", o->train.epochs,
                             "passes over the data (first grows rules, later tune); chosen "
                             "when not given")
                 ->capture_default_str()
                 ->check(CLI::Range(1, 100000));
  c.sim_steps =
      app->add_option("--simulation-steps", c.simulation_steps,
                      "with output lags: after one-step training, up to this many steps per stage "
                      "on the simulation (free-run) error, over windows each started from measured "
                      "outputs (multiple shooting), the hold-out keeping the best; on by default "
                      "while settings are chosen, 0 turns it off")
          ->capture_default_str()
          ->check(CLI::Range(0, 100000));
  app->add_option("--simulation-horizons", c.simulation_horizons,
                  "window lengths in samples, one stage each, in order")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  app->add_option("--learning-rate", c.learning_rate,
                  "online gradient rate for centres and widths (scaled units)")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 10.0));
  c.kind = app->add_option("--consequent", c.consequent,
                           "linear (Takagi–Sugeno) or singleton (the paper's, readable); "
                           "chosen when not given")
               ->capture_default_str()
               ->check(CLI::IsMember({"singleton", "linear"}));
  app->add_option("--entropy-measure", c.measure, "firing (paper) or per_input")
      ->capture_default_str()
      ->check(CLI::IsMember({"firing", "per_input"}));
  c.kappa = app->add_option("--kappa", o->model.entropy.kappa,
                            "new width = kappa · RMS distance to the nearest rule centre; chosen "
                            "when not given")
                ->capture_default_str();
  app->add_option("--sigma-min", o->model.entropy.sigma_min, "smallest width (scaled units)")
      ->capture_default_str();
  app->add_option("--forgetting", o->model.forgetting,
                  "RLS forgetting factor of linear consequents, (0, 1]; 1 never forgets")
      ->capture_default_str();
  app->add_option("--prune-utility", o->model.entropy.prune_utility,
                  "remove a rule whose mean normalised firing falls below this (0: never)")
      ->capture_default_str();
}

// Replaying the online identifier with its scheduled refits instead of selecting.
void AddRefitOptions(CLI::App* app, FitJobOptions* o) {
  app->add_option("--refit-first", o->refit.first,
                  "replay the online identifier instead (its refit_* keys): every row through its "
                  "learner, which refits with this program's defaults on --refit-buffer samples "
                  "kept after this many are learned, then 2x, 4x, ... up to --refit-every, then "
                  "every --refit-every, and once more at the end (a freeze); 0: no refits")
      ->capture_default_str()
      ->check(CLI::Range(int64_t{0}, int64_t{100000000}));
  app->add_option("--refit-every", o->refit.every,
                  "past this many samples, a refit every this many (0: doubling for ever)")
      ->capture_default_str()
      ->check(CLI::Range(int64_t{0}, int64_t{100000000}));
  app->add_option("--refit-at-freeze", o->refit.at_freeze,
                  "with --refit-first: a closing refit at the end, as the identifier's "
                  "refit_at_freeze")
      ->capture_default_str();
  app->add_flag("--replay-unfrozen", o->replay_unfrozen,
                "with --refit-first: replay an identifier stopped without a freeze (no closing "
                "refit; the refit in flight never lands)");
  app->add_option("--refit-buffer", o->refit.buffer, "samples kept for a refit")
      ->capture_default_str()
      ->check(CLI::Range(int64_t{1}, int64_t{100000000}));
  app->add_option("--refit-history", o->refit.history,
                  "the share of --refit-buffer kept as blocks spread over the whole run (the rest: "
                  "the most recent samples); 0: the most recent only")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 1.0));
}

// How settings are chosen: least squares, the candidates, the criterion, the checks.
void AddSelectionOptions(CLI::App* app, FitCli& c, FitJobOptions* o) {
  app->add_option("--ridge", o->train.ridge, "least-squares ridge, relative to the design's scale")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app->add_flag_callback(
      "--no-output-limits", [o] { o->train.detect_output_limits = false; },
      "do not hold predictions at an output's saturation (a value the training output holds for "
      "5 samples in a row and on 1 % of them; docs/identifier.md §7.2)");
  app->add_flag("--no-least-squares", c.no_ls,
                "skip the global least-squares consequent solve after each pass (pure online "
                "learning, as the online identifier does)");
  app->add_flag("--no-select", c.no_select,
                "use the defaults for every setting not given instead of choosing them");
  app->add_option("--select-criterion", c.criterion,
                  "what the choice minimises on the hold-out: auto (k-step NDEI with --horizon, "
                  "else free-run when ny > 0, else one-step), free_run, one_step or k_step")
      ->capture_default_str()
      ->check(CLI::IsMember({"auto", "free_run", "one_step", "k_step"}));
  c.deviation_ridge =
      app->add_option("--deviation-ridge", o->train.deviation_ridge,
                      "least-squares ridge on each rule's deviation from one global linear model, "
                      "relative to the design's scale (0: none); not given, the best fuzzy "
                      "candidates are also tried with 0.01, 0.1 and 1 and the hold-out chooses")
          ->capture_default_str()
          ->check(CLI::NonNegativeNumber);
  app->add_option("--min-rule-support", o->train.min_rule_support,
                  "a rule whose summed normalised firing over the training rows is below this many "
                  "times its consequent's parameter count is removed after the pass that grows "
                  "rules (0: keep every rule)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app->add_option("--cv-folds", o->selection.linear_check_folds,
                  "a fuzzy model is kept over the linear one (ARX, always a candidate) only when "
                  "it also wins this many-fold blocked cross-validation of the training file; 0 "
                  "or 1: the hold-out alone decides")
      ->capture_default_str()
      ->check(CLI::Range(0, 50));
  app->add_option("--cv-candidates", o->selection.linear_check_candidates,
                  "fuzzy candidates that may face that cross-validation: the chosen one, then, "
                  "while each loses, the next by hold-out score (the first that wins is chosen)")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000));
  app->add_option("--horizon", o->horizon,
                  "K: also score K steps ahead (each prediction a free run from the measured "
                  "outputs K samples before), and choose by it: for loops that integrate (rates, "
                  "velocities), whose free run drifts for any model; with --refit-first, the "
                  "replayed refits choose by it too (the identifier's refit_horizon)")
      ->check(CLI::Range(2, 1000000));
  app->add_option("--select-tolerance", c.tolerance_percent,
                  "keep the fewest rules within this many percent of the best hold-out NDEI")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  app->add_option("--holdout", o->selection.holdout_fraction,
                  "fraction of the training file (its end) held out for the choice")
      ->capture_default_str()
      ->check(CLI::Range(0.05, 0.5));
  app->add_option("--select", o->select_csv,
                  "selection CSV (a third excitation): score the candidates on it instead of on "
                  "the training file's end")
      ->check(CLI::ExistingFile);
  AddCsvFormatOptions(app, &c.csv_format);
  app->add_option("--search-rows", o->search_budget.rows,
                  "a longer training file's settings are chosen on this many of its rows, in " +
                      std::to_string(o->search_budget.blocks) +
                      " blocks spread over it (the hold-out is the last blocks), and the chosen "
                      "setting is then trained on every row: the search's time stays bounded "
                      "however long the log; 0 searches every row")
      ->capture_default_str()
      ->check(CLI::Range(Eigen::Index{0}, Eigen::Index{1000000000}));
  app->add_option("--select-thresholds", o->selection.thresholds, "H̄ values to try")
      ->delimiter(',');
  app->add_option("--select-kappas", o->selection.kappas, "kappa values to try")->delimiter(',');
  app->add_option("--interval-level", o->interval_level,
                  "the prediction intervals' level, printed with their coverage and width on "
                  "the validation file (split-conformal on the selection's hold-out)")
      ->capture_default_str()
      ->check(CLI::Range(0.5, 0.999));
  app->add_option("--threads", o->selection.threads,
                  "threads for the candidates' independent trainings (0: every core); the model "
                  "is the same whatever the count")
      ->capture_default_str()
      ->check(CLI::Range(0u, 1024u));
  app->add_option("--max-epochs", o->selection.max_epochs,
                  "most epochs a candidate trains (the best hold-out epoch is kept)")
      ->capture_default_str()
      ->check(CLI::Range(1, 100000));
}

// What is written and printed.
void AddOutputOptions(CLI::App* app, FitCli& c, FitJobOptions* o) {
  app->add_option("--seed", o->seed,
                  "recorded in the report; the learning itself uses no randomness")
      ->capture_default_str();
  app->add_option("--save-model", o->save_model, "write the model as JSON");
  app->add_option("--load-model", o->load_model, "evaluate a saved model instead of training")
      ->check(CLI::ExistingFile);
  app->add_option("--predictions", o->predictions,
                  "write a CSV: set (0 train, 1 validate), sample, measured, fuzzy_one_step, "
                  "fuzzy_free_run, arx_one_step, arx_free_run");
  app->add_option(
         "--track", o->track_csv,
         "after training, learn online over this CSV beside a frozen copy and ARX, with an "
         "accuracy alarm on each (a vehicle that changes mid-run)")
      ->check(CLI::ExistingFile);
  app->add_option("--track-output", o->track_output,
                  "per-sample CSV of the --track run: measured, online, frozen, arx and their "
                  "window FIT");
  app->add_option("--track-window", o->track_window,
                  "samples in the --track run's accuracy window and alarm: one second of data "
                  "(100 at 100 Hz, 20 at 20 Hz)")
      ->capture_default_str()
      ->check(CLI::Range(5, 100000));
  app->add_option("--track-forgetting", o->track_forgetting,
                  "forgetting factor of the model learning over --track, in (0, 1] (default: the "
                  "trained model's); 1 − 1/(samples per second) forgets in about a second")
      ->check(CLI::Range(1e-6, 1.0));
  app->add_option("--ranges", o->ranges,
                  "JSON {signal: [min, max]}: fixes the scaling instead of deriving it from the "
                  "training data (what the online identifier uses)")
      ->check(CLI::ExistingFile);
  app->add_option("--save-ranges", o->save_ranges,
                  "write the training data's signal ranges as JSON");
  app->add_option("--save-config", o->save_config,
                  "write an odonata-identifier configuration: these signals and lags, the chosen "
                  "settings, the training data's ranges (or --ranges), \"source\": \"signals\" "
                  "(any vehicle's signals_t; set \"dimav\" for the DI-MAV's own messages)");
  app->add_flag("--rules", c.rules,
                "list the rules as sentences, in the readable form: shared named terms, lags as "
                "one clause, rules that read alike as one, with each rule's dynamics");
  app->add_flag("--full-rules", c.full_rules, "list every rule of the full model instead");
  app->add_option(
      "--plot", o->plot_dir,
      "draw the model into this directory (python3, matplotlib): each signal's readable "
      "terms, which rule fires when along the validation run, and the output surface "
      "of a static map or the gain schedule of a dynamic one; the data beside them");
  app->add_option("--report", c.report_dir,
                  "write a page for this fit into DIR (DIR/index.html): the verdict beside ARX and "
                  "persistence, the compare plot, the readable rules with time constants, the "
                  "pictures (--plot), the data's excitation and windows, the command");
  app->add_flag("--json", c.json, "print one JSON object on stdout");
}

}  // namespace

void AddFitOptions(CLI::App* app, FitCli& c, FitJobOptions* o) {
  c.consequent = fuzzy::ToString(o->model.consequent);
  c.learning_rate = o->model.rates.centre;
  c.tolerance_percent = 100 * o->selection.relative_tolerance;
  o->spec.output_lags = 1;
  o->spec.input_lags = 1;
  o->spec.delay = 1;
  AddDataOptions(app, o);
  AddWindowOptions(app, c, o);
  AddLearnerOptions(app, c, o);
  AddRefitOptions(app, o);
  AddSelectionOptions(app, c, o);
  AddOutputOptions(app, c, o);
}

void ApplyFitCli(const FitCli& c, FitJobOptions& o) {
  if (o.load_model.empty()) {
    if (o.train_csv.empty()) throw std::runtime_error("--train is required (or --load-model)");
    if (o.outputs.empty()) throw std::runtime_error("--output is required");
  }
  if (c.airborne && !c.keep_when.empty())
    throw std::runtime_error("--airborne is --keep-when vehicle_land_detected.landed==0: give one");
  if (c.airborne) o.keep = timeseries::Px4Airborne();
  if (!c.keep_when.empty()) o.keep = timeseries::ParseKeepCondition(c.keep_when);
  if (!c.time_unit.empty())
    o.time_unit_s = c.time_unit == "ms" ? 1e-3 : c.time_unit == "us" ? 1e-6 : 1.0;
  if (!c.report_dir.empty()) {
    o.plot_dir = c.report_dir;
    if (o.predictions.empty()) o.predictions = c.report_dir + "/predictions.csv";
  }
  o.model.consequent = fuzzy::ConsequentKindFromString(c.consequent);
  o.model.entropy.measure =
      c.measure == "firing" ? fuzzy::EntropyMeasure::kFiring : fuzzy::EntropyMeasure::kPerInput;
  o.model.rates.centre = c.learning_rate;
  o.model.rates.sigma = c.learning_rate;
  o.train.refine_least_squares = !c.no_ls;
  o.select = !c.no_select;
  o.consequent_given = c.kind->count() > 0;
  o.threshold_given = c.threshold->count() > 0;
  o.kappa_given = c.kappa->count() > 0;
  o.epochs_given = c.epochs->count() > 0;
  if (c.deviation_ridge->count() > 0) o.selection.deviation_ridges.clear();
  o.selection.relative_tolerance = c.tolerance_percent / 100.0;
  o.selection.criterion = c.criterion == "auto"       ? sysid::SelectionCriterion::kAuto
                          : c.criterion == "free_run" ? sysid::SelectionCriterion::kFreeRun
                          : c.criterion == "k_step"   ? sysid::SelectionCriterion::kAhead
                                                      : sysid::SelectionCriterion::kOneStep;
  // Without least squares (the online learner), only one pass means anything online.
  if (c.no_ls && !o.epochs_given) {
    o.train.epochs = 1;
    o.epochs_given = true;
  }
  o.simulation.clear();
  for (const int h : c.simulation_horizons) o.simulation.push_back({h, c.simulation_steps});
  if (c.simulation_steps == 0) o.simulation.clear();
  o.simulation_given = c.sim_steps->count() > 0;
  // A bar on a terminal; into a log, a line every 10 s, unless the output is JSON for a pipe.
  o.progress = StderrIsTerminal() ? ProgressStyle::kBar
               : c.json           ? ProgressStyle::kOff
                                  : ProgressStyle::kLines;
}

}  // namespace odonata::fit

#pragma once
// odonata-fit's work, separate from argument parsing so tests can run it in-process.

#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "fit/progress_bar.hpp"
#include "fuzzy/fuzzy_model.hpp"
#include "io/csv_table.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"
#include "sysid/model/series_from_table.hpp"
#include "sysid/online/scheduled_refitter.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/search_subsample.hpp"
#include "timeseries/keep_condition.hpp"

namespace odonata::fit {

struct FitJobOptions {
  std::string train_csv;             ///< empty only with load_model
  std::string validate_csv;          ///< optional
  std::vector<std::string> outputs;  ///< columns to identify (one model each, one regressor)
  std::vector<std::string> inputs;   ///< input columns
  sysid::RegressorSpec spec;         ///< lags and delay (names filled from output/inputs)
  fuzzy::FuzzyModelConfig model;     ///< entropy, cap, rates, consequent
  sysid::TrainOptions train;
  /// Enabled: replay the online identifier's learner with this schedule over the training file
  /// (sysid::LearnOnline) instead of selecting and training; the given settings are its config.
  sysid::RefitSchedule refit;
  bool replay_unfrozen = false;  ///< the replayed identifier was never frozen
  unsigned long seed = 0;        ///< shuffles nothing today; recorded for reproducibility
  std::string save_model;        ///< optional path
  std::string load_model;        ///< optional: evaluate this model instead of training
  /// Settings the user fixed; the others are chosen on a hold-out slice of the training data
  /// (unless select is false, which keeps the defaults).
  bool select = true;
  bool consequent_given = false;
  bool threshold_given = false;
  bool kappa_given = false;
  bool epochs_given = false;
  sysid::SelectionOptions selection;
  /// A long training file's settings are chosen on this many of its rows (blocks spread over
  /// it), then trained on all of them; rows = 0 searches the whole file.
  sysid::SearchSubsample search_budget;
  std::string predictions;  ///< optional CSV of measured, fuzzy and ARX predictions
  /// Optional directory for the pictures (fit_plot_data.hpp): their data, and the PNGs drawn.
  std::string plot_dir;
  /// Optional selection CSV (a third excitation): candidates train on all of --train and are
  /// scored on it, instead of on a hold-out slice of --train.
  std::string select_csv;
  /// Optional: after training, run the model online over this CSV (it keeps learning, as the
  /// online identifier does), beside a frozen copy and the ARX model fitted on --train, with the
  /// accuracy alarm on each; a vehicle that changes mid-run shows what online learning is for.
  std::string track_csv;
  std::string track_output;  ///< optional per-sample CSV of the tracking run
  /// Samples in the tracking run's accuracy window (and the alarm's): one second of data,
  /// 100 at 100 Hz, 20 after decimation by 5.
  int track_window = 100;
  /// RLS forgetting factor of the model that keeps learning over --track (0: keep the trained
  /// model's), as `odonata-control set-forgetting` sets it on a running identifier.
  double track_forgetting = 0.0;
  ProgressStyle progress = ProgressStyle::kOff;  ///< progress on stderr
  /// Real logs (docs/identifier.md §7.1): a time column resampled to `rate_hz` (0: the file's
  /// median rate), and gaps of at most `max_gap` samples bridged, longer ones cut into segments.
  std::string time_column;
  double time_unit_s = 0;    ///< seconds per unit of time_column (0: from its name, else 1)
  io::CsvFormat csv_format;  ///< the CSV files' delimiter and decimal mark
  double rate_hz = 0;
  int max_gap = 3;
  /// Every file is read only inside this window, seconds on its own time axis (a ULog's: since
  /// its start), and only where `keep` holds (PX4's airborne part: timeseries::Px4Airborne()).
  double from_s = -std::numeric_limits<double>::infinity();
  double to_s = std::numeric_limits<double>::infinity();
  std::optional<timeseries::KeepCondition> keep;
  /// Told what the user should know while the job runs (the grid a log is put on); may be empty.
  std::function<void(const std::string&)> note;
  /// Simulation-error training (simulation_error_training.hpp) after one-step training, with
  /// output lags: while settings are chosen, the short list's candidates take it with the
  /// hold-out keeping the best step; with every setting given, only when simulation_given.
  /// Never with train.refine_least_squares off: the online learner has no such phase.
  std::vector<sysid::SimulationStage> simulation = sysid::DefaultSimulationStages();
  bool simulation_given = false;
  /// K > 1: also score K steps ahead (k_step in the report), and choose by it unless the
  /// selection criterion says otherwise.
  int horizon = 0;
  /// The prediction intervals' level (prediction_intervals.hpp), in (0, 1).
  double interval_level = 0.9;
  std::string ranges;       ///< optional: declared signal ranges (JSON) fix the scaling
  std::string save_ranges;  ///< optional: write the training data's ranges (JSON)
  /// Optional: write an odonata-identifier configuration with the chosen settings (JSON).
  std::string save_config;
};

/// Runs the job and returns the report (the --json document).
/// @throws sysid::NothingToIdentify when the data holds nothing a model can be identified from
///   (saying what to do), std::runtime_error (or io::CsvError) with a message naming file, line
///   and column.
nlohmann::json RunFitJob(const FitJobOptions& options);

}  // namespace odonata::fit

#pragma once
// odonata-identifier's configuration file (JSON): its one reader and its one writer.

#include <string>

#include <nlohmann/json.hpp>

#include "bus/channel_config.hpp"
#include "fuzzy/fuzzy_model.hpp"
#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/signal_ranges.hpp"
#include "sysid/online/scheduled_refitter.hpp"

namespace odonata::identifier {

/// Where samples come from: the DI-MAV's commands, states and beat states paired by seq, or any
/// vehicle's signals_t, one message per sample with every signal by name (docs/lcm.md §14).
enum class SampleSource { kDimav, kSignals };

struct IdentifierConfig {
  std::string instance = "identifier";
  SampleSource source = SampleSource::kDimav;
  sysid::RegressorSpec spec;       ///< outputs, inputs (signal names), ny, nu, delay
  fuzzy::FuzzyModelConfig model;   ///< consequent, entropy threshold, cap
  sysid::SignalRanges ranges;      ///< declared ranges: the model's fixed scaling
  double snapshot_period_s = 1.0;  ///< model snapshot publication period (0: on request only)
  /// Also publish a snapshot every N learned samples (0: off). 100 by default, as the guide says:
  /// a kill -9 then costs at most 100 samples even while a refit holds the 1 s timer up.
  int64_t snapshot_every_samples = 100;
  double resume_wait_s = 1.0;  ///< wait this long for a snapshot to resume from
  /// Learn from one sample per block of this many (io::RowDecimator, as odonata-sim --decimate
  /// and odonata-logger export --decimate cut them): 5 identifies at 20 Hz from a 100 Hz plant.
  int decimate = 1;
  /// The longest run of missing samples (lost in real time) bridged by interpolation instead of
  /// restarting the history, as odonata-fit --max-gap bridges missing rows (0: none).
  int max_gap = 3;
  /// Refits of the model with odonata-fit's learner on the samples it keeps, at fixed counts
  /// (docs/identifier.md §6.3): "refit_first" (0: none), "refit_every", "refit_buffer",
  /// "refit_history", "refit_at_freeze", "refit_horizon".
  sysid::RefitSchedule refit = sysid::RefitSchedule::IdentifierDefault();
  bus::ChannelConfig channels;
};

/// Reads and checks the file, reporting every problem at once.
/// @throws std::runtime_error naming the file and each problem.
IdentifierConfig LoadIdentifierConfig(const std::string& path);

/// The same from JSON text; `origin` names it in errors.
/// @throws std::runtime_error naming `origin` and each problem.
IdentifierConfig ParseIdentifierConfig(const std::string& text, const std::string& origin);

/// Every key of `config`, as LoadIdentifierConfig reads them: the one writer of the file.
nlohmann::ordered_json IdentifierConfigToJson(const IdentifierConfig& config);

/// The configuration used without --config: ExampleIdentifierConfig(), the roll loop.
IdentifierConfig DefaultIdentifierConfig();

/// The example configuration printed by --print-config.
std::string ExampleIdentifierConfig();

}  // namespace odonata::identifier

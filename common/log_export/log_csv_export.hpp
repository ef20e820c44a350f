#pragma once
// Turns a recorded event log into the CSV odonata-sim writes (and odonata-fit reads): row k is
// sample k as the online identifier pairs it (messages/paired_sample.hpp): state k, the command
// state k + 1 answers and, when the log holds beat states, beat state k's averages and beat
// state k + 1's applied-command channels (the command applied over [t_k, t_k+1)). Its runs are
// the identifier's too: a plant restart starts one once the plant confirms it.

#include <string>
#include <utility>
#include <vector>

namespace odonata::log_export {

struct ExportOptions {
  std::string command_channel = "DIMAV_COMMAND";
  std::string state_channel = "DIMAV_STATE";
  std::string beat_state_channel = "DIMAV_BEAT_STATE";  ///< optional: older logs have none
  /// Which run (a confirmed plant restart starts one); negative counts from the end over the runs
  /// that hold samples (a run of states alone, e.g. a plant reset twice, is skipped).
  int run = -1;
  /// One row per block of this many samples (io::RowDecimator: commands, excitations and
  /// applied channels averaged, the rest at the block's first sample), as odonata-sim
  /// --decimate and an identifier configured with "decimate" cut them. @pre ≥ 1.
  int decimate = 1;
};

struct ExportSummary {
  int runs = 0;           ///< runs found in the log(s)
  int exported_run = -1;  ///< the run written
  long rows = 0;
  long undecodable = 0;       ///< events on the three channels that did not decode (skipped)
  bool beat_columns = false;  ///< the log had beat states: _avg and _applied_ columns written
  long incomplete = 0;        ///< samples lost for a missing state, command or beat state (gaps)
  long rejected = 0;          ///< messages the pairing rules reject (out of order, a leap, a
                              ///< second command for a seq): the identifier drops them too
  long dropped_blocks = 0;    ///< with decimation: blocks given up for a missing sample
};

/// Reads the logs in order (a rotated log's files, oldest first) and writes `csv_path`. Columns:
/// t_s, the 24 commands received, the state, the excitations, and, if the run has beat states,
/// the beat averages and applied channels (experiments/sample_columns.hpp: odonata-sim's names;
/// a sample missing either beat state is then incomplete).
/// @throws std::runtime_error naming the file on unreadable logs, no samples, or write errors.
ExportSummary ExportLogToCsv(const std::vector<std::string>& log_paths, const std::string& csv_path,
                             const ExportOptions& options);

struct SignalsExportSummary {
  int runs = 0;           ///< runs found (a vehicle's seq going back starts one)
  int exported_run = -1;  ///< the run written
  long rows = 0;
  long undecodable = 0;  ///< events on the channel that did not decode or had bad counts
  long dropped = 0;      ///< duplicates, stale seqs and unconfirmed leaps (all runs)
  long foreign = 0;      ///< messages of the run whose signal names differ from its first one
  long lost = 0;         ///< seqs missing in the run (rows not written: see the seq column)
  /// Vehicle signals written under another name, (theirs, the column's): a signal named like a
  /// column the export adds (seq, t_s), or like an earlier signal, would make a header that no
  /// CSV reader takes. Said in the file's header comment too.
  std::vector<std::pair<std::string, std::string>> renamed;
};

/// Any vehicle's signals_t on `channel` (docs/lcm.md §14) as CSV: columns seq, t_s (seconds since
/// the run's first message, from utime) and every signal of the run's first message, in its
/// order (one named like a column before it gets the suffix _vehicle, or _vehicle2 …: renamed); one
/// row per sample the identifier would take, in the order it would take them
/// (sequence/sample_sequence.hpp: runs, gaps and drops alike). `run` as in ExportOptions.
/// @throws std::runtime_error on unreadable logs, no signals, or write errors.
SignalsExportSummary ExportSignalsToCsv(const std::vector<std::string>& log_paths,
                                        const std::string& channel, const std::string& csv_path,
                                        int run = -1);

/// Writes every prediction_t on `channel` as CSV: run, sample, learning, and per output
/// NAME_measured, NAME_predicted, NAME_free_run, NAME_next, NAME_rules, NAME_max_entropy,
/// NAME_arx_predicted, NAME_arx_free_run, and with a horizon K carried by every prediction
/// NAME_ahead_K and NAME_arx_ahead_K (ŷ(k | k−K)). A new run starts when the sample number goes
/// back. Returns the rows written.
/// @throws std::runtime_error on unreadable logs or when there is no prediction.
long ExportPredictionsToCsv(const std::vector<std::string>& log_paths, const std::string& channel,
                            const std::string& csv_path);

/// Scores every prediction_t on `channel` as odonata-monitor does (monitoring/
/// prediction_scoreboard.hpp: one-step and free-run accuracy per output, run by run, the sample
/// number going back starting a run) and writes the scoreboard's summary as JSON: the last run
/// at the top level, the earlier ones under "previous_runs". From the log, so a monitor that
/// missed packets does not change the figures. "predictions_missing" (and `*missing`) counts
/// the predictions published but not in the log (gaps in the identifier's message counter: lost
/// on the way, or while the logger was down). Returns the predictions scored.
/// @throws std::runtime_error on unreadable logs, no prediction, or a write error.
long ScorePredictionsToJson(const std::vector<std::string>& log_paths, const std::string& channel,
                            const std::string& json_path, int64_t* missing = nullptr);

/// Writes every model_snapshot_t on `channel` as a JSON array of
/// {"utime", "samples_learned", "instance", "model": <odonata-fit model JSON>}.
/// Returns the snapshots written.
long ExportSnapshotsToJson(const std::vector<std::string>& log_paths, const std::string& channel,
                           const std::string& json_path);

}  // namespace odonata::log_export

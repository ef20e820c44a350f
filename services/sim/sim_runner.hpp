#pragma once
// Core of odonata-sim: runs a command sequence through the plant and writes the CSV that
// odonata-fit reads. No CLI parsing here, so it can be tested and reused.

#include <string>
#include <vector>

#include "experiments/experiment_preset.hpp"
#include "plant/dimav_plant.hpp"

namespace odonata::sim {

/// Outcome of a run.
struct SimResult {
  std::size_t rows_written{};
  bool stopped{};                     ///< the plant diverged with policy "stop"; the CSV ends there
  int resets{};                       ///< divergences handled by policy "reset"
  std::vector<std::string> messages;  ///< one per divergence, for stderr
};

/// The CSV header (experiments/sample_columns.hpp): t_s, the commands, the outputs,
/// `extra_columns` (the excitation), the beat averages and, with `applied_columns`, the
/// applied-command channels.
std::vector<std::string> CsvHeader(const std::vector<std::string>& extra_columns,
                                   bool applied_columns = false);

/// Runs `run.commands` from `run.initial` and writes one row per sample: row k holds t_k, the
/// command applied over [t_k, t_k+1) and the outputs at t_k (so y(k+1) responds to u(k)).
/// The w{i}_* columns are the command actually applied (attitude hold added, clamped); the
/// excitation columns are the designed excitation; the *_applied_* columns (runs with
/// record_applied) are the excitation's channels read from the applied command.
///
/// With decimate = N > 1 one row is written per block of N samples (a lower, e.g. wing-beat,
/// rate): the outputs (instantaneous and _avg) at the block's first sample t_jN, the inputs
/// (w{i}_*, excitation and applied columns) averaged over the block, i.e. the mean input held
/// over [t_jN, t_(j+1)N). A partial last block is not written.
/// @pre decimate ≥ 1.
/// @throws std::runtime_error if the file cannot be written.
SimResult RunAndWrite(const plant::PlantConfig& config, const experiments::ExperimentRun& run,
                      const std::string& output_path, int decimate = 1);

/// Reads a command file (columns t_s and the 24 command names, any order, other columns ignored),
/// checking that t_s is uniformly spaced at the plant's sample period.
/// @throws std::runtime_error naming the file and the problem.
experiments::ExperimentRun ReadCommandFile(const std::string& path,
                                           const plant::PlantConfig& config,
                                           double start_altitude_m);

}  // namespace odonata::sim

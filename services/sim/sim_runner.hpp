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

/// The CSV header: t_s, the 24 commands (w{i}_beta_rad … w{i}_phase_rad), the outputs
/// (vx_mps … z_m, fx{1..4}_n, fz{1..4}_n) and then `extra_columns`.
std::vector<std::string> CsvHeader(const std::vector<std::string>& extra_columns);

/// Runs `run.commands` from `run.initial` and writes one row per sample: row k holds t_k, the
/// command applied over [t_k, t_k+1) and the outputs at t_k (so y(k+1) responds to u(k)).
/// @throws std::runtime_error if the file cannot be written.
SimResult RunAndWrite(const plant::PlantConfig& config, const experiments::ExperimentRun& run,
                      const std::string& output_path);

/// Reads a command file (columns t_s and the 24 command names, any order, other columns ignored),
/// checking that t_s is uniformly spaced at the plant's sample period.
/// @throws std::runtime_error naming the file and the problem.
experiments::ExperimentRun ReadCommandFile(const std::string& path,
                                           const plant::PlantConfig& config,
                                           double start_altitude_m);

}  // namespace odonata::sim

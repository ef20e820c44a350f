#pragma once
// The command sequence a signal generator sends: from an experiment preset (exactly the commands
// odonata-sim runs) or from a command CSV.

#include <cstdint>
#include <string>
#include <vector>

#include "experiments/experiment_preset.hpp"
#include "plant/plant_config.hpp"
#include "plant/wing_command.hpp"

namespace odonata::pipeline {

/// Commands to send, one per sample, with their scalar excitations.
struct CommandSchedule {
  std::vector<plant::CommandMatrix> commands;          ///< command k is applied over [t_k, t_k+1)
  std::vector<std::string> excitation_names;           ///< e.g. "u_roll_rad"
  std::vector<std::vector<double>> excitation_values;  ///< [signal][sample]
  double sample_period_s{};                            ///< t_k = k · sample_period_s
  std::string source;      ///< "preset:roll/train" or the command file's path
  std::string setup_name;  ///< preset whose initial condition the plant should use ("" = its own)

  std::size_t size() const { return commands.size(); }
  /// t_k in s, computed as odonata-sim computes its t_s column.
  double TimeOf(std::size_t k) const { return static_cast<double>(k) * sample_period_s; }
};

/// The commands of BuildExperimentRun() (bit-identical to odonata-sim's for the same arguments).
/// @param duration_s ≤ 0 selects the preset's default for the phase.
/// @throws std::runtime_error for an empty run or a configuration without hover trim.
CommandSchedule PresetSchedule(const experiments::ExperimentPreset& preset,
                               experiments::Phase phase, std::uint64_t seed, double duration_s,
                               const plant::PlantConfig& config);

/// Reads a command CSV as odonata-sim does: t_s (uniform at the plant's sample period) and the
/// 24 command columns in any order. Columns named u_* are sent as excitations (a CSV written by
/// odonata-sim can be replayed as it is); other columns are ignored. Every command must be inside
/// the actuator limits, so a run never stalls on a command the plant would reject.
/// @param duration_s > 0 keeps only the first duration_s / sample period rows.
/// @throws std::runtime_error naming the file and every problem found.
CommandSchedule FileSchedule(const std::string& path, const plant::PlantConfig& config,
                             double duration_s);

}  // namespace odonata::pipeline

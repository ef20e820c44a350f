#pragma once
// The paper's six identification experiments (section IV) as reproducible presets.

#include <cstdint>
#include <string>
#include <vector>

#include "experiments/attitude_hold.hpp"
#include "plant/actuator_damage.hpp"
#include "plant/dimav_plant.hpp"
#include "plant/plant_config.hpp"
#include "plant/trim_finder.hpp"
#include "plant/wing_command.hpp"

namespace odonata::experiments {

/// Training data or the (different) validation data of an experiment.
enum class Phase { kTrain, kValidate };

/// What an experiment excites and what the identifier should do with the data.
struct ExperimentPreset {
  std::string name;         ///< CLI name, e.g. "roll"
  std::string description;  ///< one line
  // Identification (docs/identifier.md §7 and §10).
  std::string output_column;               ///< CSV column of y
  std::vector<std::string> input_columns;  ///< CSV column(s) of u
  int ny{};                                ///< suggested output lags
  int nu{};                                ///< suggested input lags
  int delay{};                             ///< suggested input delay (samples)
  double entropy_threshold{};              ///< H̄ to use (the paper's final value)
  std::string paper_entropy_text;          ///< the paper's H̄ as reported
  int paper_mf_count{};                    ///< membership functions the paper reports
  std::string paper_accuracy_text;         ///< accuracy the paper reports
  // Run.
  double train_duration_s{};
  double validate_duration_s{};
  bool clamped_body{};              ///< test stand (actuator experiments) instead of free flight
  double start_altitude_m{};        ///< world z of the centre of mass at t = 0 (free flight)
  bool attitude_hold{};             ///< fly with the slow roll/pitch hold (see attitude_hold.hpp)
  std::string train_excitation;     ///< human-readable training excitation
  std::string validate_excitation;  ///< human-readable validation excitation
};

/// Commands and excitation of one run, sampled at the plant's sample rate.
struct ExperimentRun {
  std::vector<plant::CommandMatrix> commands;  ///< sample k is applied over [t_k, t_k+1)
  std::vector<std::string> excitation_names;   ///< extra scalar CSV columns (e.g. "u_roll_rad")
  std::vector<std::vector<double>> excitation_values;  ///< [column][sample]
  plant::InitialCondition initial{};                   ///< start state (hover trim, in the air)
  plant::TrimResult trim{};                            ///< the hover trim used
  bool attitude_hold{};            ///< close the slow roll/pitch hold around the plant
  AttitudeHoldGains hold_gains{};  ///< its gains (free-flight presets)
  double sample_period_s{};
  /// Samples whose designed command left the actuator limits and was clamped: a well-designed
  /// excitation has none, since clamping distorts the spectrum it was designed to have.
  std::size_t clamped_samples{};
  /// A wing that fails mid-run (the damage scenario); none by default. The commands above stay
  /// what was commanded; the plant flies damage.Apply(command, t).
  plant::ActuatorDamage damage{};
};

/// The six presets, in the paper's order: actuator_fz, actuator_fx, vertical_velocity, roll,
/// pitch, yaw.
const std::vector<ExperimentPreset>& Presets();

/// The preset called `name`, or nullptr.
const ExperimentPreset* FindPreset(const std::string& name);

/// Comma-separated preset names, for error messages.
std::string PresetNames();

/// "train" / "validate".
const char* PhaseName(Phase phase);

/// Builds the command sequence of a run around hover trim, clamped to the actuator limits.
/// Deterministic: the same (preset, phase, seed, duration, config) gives bit-identical commands.
/// Training and validation use different signals and different random streams for any seed.
/// @param duration_s ≤ 0 selects the preset's default for the phase.
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
ExperimentRun BuildExperimentRun(const ExperimentPreset& preset, Phase phase, std::uint64_t seed,
                                 double duration_s, const plant::PlantConfig& config);

}  // namespace odonata::experiments

#pragma once
// The paper's six identification experiments (section IV) as reproducible presets.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "plant/actuator_damage.hpp"
#include "plant/dimav_plant.hpp"
#include "plant/plant_config.hpp"
#include "plant/trim_finder.hpp"
#include "plant/wing_command.hpp"
#include "vehicle/attitude_hold.hpp"
#include "vehicle/wing_channels.hpp"

namespace odonata::experiments {

/// The three excitations of an experiment, all different signals and random streams:
/// training (the model learns from it), selection (every choice — H̄, widths, model order — is
/// scored on it) and validation (the final score, never used for a choice).
enum class Phase { kTrain, kValidate, kSelect };

struct ExcitationContext;  // preset_kit.hpp
struct RunBuilder;

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
  double select_duration_s{};
  bool clamped_body{};              ///< test stand (actuator experiments) instead of free flight
  double start_altitude_m{};        ///< world z of the centre of mass at t = 0 (free flight)
  bool attitude_hold{};             ///< fly with the slow roll/pitch hold (see attitude_hold.hpp)
  std::string train_excitation;     ///< human-readable training excitation
  std::string validate_excitation;  ///< human-readable validation excitation
  std::string select_excitation;    ///< human-readable selection excitation
  /// The input is the excitation before the onboard attitude hold adds its correction, so the
  /// model is of the held (closed-loop) vehicle; the name ends in "_held". Otherwise the input
  /// is what the wings did (an *_applied_* column, or a command on the test stand).
  bool held_vehicle{};
  /// Identify from one row per this many samples (odonata-sim --decimate: inputs averaged over
  /// the block, outputs at its first sample); 1 for the paper's six, which use every sample.
  int decimate = 1;
  /// Not one of the paper's six: an experiment where the physics is nonlinear (a wide operating
  /// range, a static force map, a coupled state), there to show what a fuzzy model adds.
  bool beyond_paper{};
  /// The damage scenarios: what fails during the validation run (a vehicle that changes in
  /// flight), which the online identifier must follow while it keeps learning. Never by default.
  plant::ActuatorDamage validate_damage{};
  /// The run's commands for a phase, built by the preset's family (actuator_presets.cpp,
  /// attitude_presets.cpp, beyond_paper_presets.cpp: each preset's table entry and excitation in
  /// one place); a held variant keeps its base preset's.
  std::function<void(const ExcitationContext&, RunBuilder&)> excite;
};

/// Commands and excitation of one run, sampled at the plant's sample rate.
struct ExperimentRun {
  std::vector<plant::CommandMatrix> commands;  ///< sample k is applied over [t_k, t_k+1)
  std::vector<std::string> excitation_names;   ///< extra scalar CSV columns (e.g. "u_roll_rad")
  std::vector<std::vector<double>> excitation_values;  ///< [column][sample]
  plant::InitialCondition initial{};                   ///< start state (hover trim, in the air)
  plant::TrimResult trim{};                            ///< the hover trim used
  bool attitude_hold{};  ///< close the slow roll/pitch hold around the plant
  /// Write the applied-command columns (AppliedChannelNames()) beside the excitation: set for
  /// the free-flight presets, whose applied command differs from the designed one by the hold.
  bool record_applied{};
  vehicle::AttitudeHoldGains hold_gains{};  ///< its gains (free-flight presets)
  double sample_period_s{};
  /// Samples whose designed command left the actuator limits and was clamped: a well-designed
  /// excitation has none, since clamping distorts the spectrum it was designed to have.
  std::size_t clamped_samples{};
  /// A wing that fails mid-run (the damage scenario): the preset's validate_damage in its
  /// validation phase, none otherwise. The commands above stay what was commanded; the plant
  /// flies damage.Apply(command, t).
  plant::ActuatorDamage damage{};
};

/// The six presets, in the paper's order: actuator_fz, actuator_fx, vertical_velocity, roll,
/// pitch, yaw; then the held-vehicle variants roll_held and pitch_held (the same runs, identified
/// from the excitation before the hold); then the experiments beyond the paper, where the physics
/// is nonlinear: vertical_wide, force_map_fz, roll_coupled; then the damage scenarios
/// wing_damage and battery_sag, whose validation run changes the vehicle halfway.
const std::vector<ExperimentPreset>& Presets();

/// The preset called `name`, or nullptr.
const ExperimentPreset* FindPreset(const std::string& name);

/// Comma-separated preset names, for error messages.
std::string PresetNames();

/// "train" / "validate" / "select".
const char* PhaseName(Phase phase);
/// The phase called `name` ("train", "select", "validate"), or nullopt.
std::optional<Phase> ParsePhase(const std::string& name);
/// The phase names for command-line checks, in run order: train, select, validate.
const std::vector<std::string>& PhaseNames();
/// The preset's default duration (s) of `phase`.
double PhaseDurationS(const ExperimentPreset& preset, Phase phase);

/// Builds the command sequence of a run around hover trim, clamped to the actuator limits.
/// Deterministic: the same (preset, phase, seed, duration, config) gives bit-identical commands.
/// Training, selection and validation use different signals and different random streams for
/// any seed.
/// @param duration_s ≤ 0 selects the preset's default for the phase.
/// @throws std::runtime_error if the configuration has no hover trim within the limits.
ExperimentRun BuildExperimentRun(const ExperimentPreset& preset, Phase phase, std::uint64_t seed,
                                 double duration_s, const plant::PlantConfig& config);

}  // namespace odonata::experiments

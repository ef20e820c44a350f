#pragma once
// What the preset families (actuator_presets.cpp, attitude_presets.cpp, beyond_paper_presets.cpp)
// build their presets and excitations from: the run being built, the phase's random streams, the
// wing groups and the paper's shared settings. Internal to experiments/: each preset keeps its
// table entry and its excitation together in its family's file, and BuildExperimentRun only
// sets up what every run shares before calling the preset's excitation.

#include <cstddef>
#include <cstdint>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "experiments/experiment_preset.hpp"
#include "plant/plant_config.hpp"
#include "plant/trim_finder.hpp"
#include "plant/wing_command.hpp"
#include "vehicle/wing_channels.hpp"

namespace odonata::experiments {

// Every free-flight experiment starts at hover trim this high: far enough that no preset reaches
// the ground within its run, so the ground never shapes identification data.
inline constexpr double kStartAltitudeM = 50.0;
// Fade-in/out of zero-mean attitude excitations (s).
inline constexpr double kRampS = 1.0;
// The paper's noise power (section IV-B1), 1-ohm convention: variance 0.01, σ = 0.1 rad.
inline constexpr double kNoisePowerW = 0.01;
// Cut at ±2.5σ (power kept, see GaussianNoise) so chirp + noise never meets the φ₀ limit.
inline constexpr double kNoiseClipSigmas = 2.5;
inline constexpr const char* kNotInPaper = "not in the paper";

// The wing groups and the channels they make (vehicle/wing_channels.hpp).
using vehicle::kBack;
using vehicle::kFront;
using vehicle::kLeft;
using vehicle::kRight;
using vehicle::PitchChannelRad;
using vehicle::RollChannelRad;
using vehicle::VerticalChannelRad;
using vehicle::YawChannelRad;

/// Independent random stream per (seed, phase, purpose).
std::mt19937_64 Stream(std::uint64_t seed, Phase phase, std::uint64_t purpose);
double RandomPhaseRad(std::uint64_t seed, Phase phase, std::uint64_t purpose);
std::uint64_t NoiseSeed(std::uint64_t seed, Phase phase);
/// Seed of an APRBS stream: independent per (seed, phase, purpose), like the chirp phases.
std::uint64_t AprbsSeed(std::uint64_t seed, Phase phase, std::uint64_t purpose);
/// Mean flapping frequency of the four wings (Hz).
double MeanFrequencyHz(const plant::CommandMatrix& c);

/// One signal per phase, the selection and validation signals of the same family as training's.
template <class Train, class Select, class Validate>
double ByPhase(Phase phase, const Train& train, const Select& select, const Validate& validate,
               double t_s) {
  switch (phase) {
    case Phase::kTrain:
      return train.Value(t_s);
    case Phase::kSelect:
      return select.Value(t_s);
    case Phase::kValidate:
      break;
  }
  return validate.Value(t_s);
}

/// Builds a run where `fill(t_s, command)` writes sample k's command (starting from the trim
/// command) and its scalar excitation u. Commands are clamped; u is recomputed by `applied` (one
/// of the *ChannelRad readers) from the clamped command, so the excitation column is exactly the
/// designed command's channel. What the wings did also holds the attitude hold's correction:
/// that is the *_applied_* column odonata-sim writes from the command it applies.
struct RunBuilder {
  const plant::PlantConfig& config;
  const plant::TrimResult& trim;
  ExperimentRun run;

  void Fill(std::size_t samples, double dt_s,
            const std::function<void(double, plant::CommandMatrix*)>& fill,
            const std::function<double(const plant::CommandMatrix&)>& applied,
            const std::string& excitation_name);
  /// One more scalar column, read from the (clamped) commands already filled.
  void AddExcitation(const std::string& name,
                     const std::function<double(const plant::CommandMatrix&)>& channel);
};

/// What a preset's excitation knows of its run.
struct ExcitationContext {
  const ExperimentPreset& preset;
  Phase phase;
  std::uint64_t seed;
  double t_end_s;
  double dt_s;
  std::size_t samples;
  const plant::TrimResult& trim;
  double a0;                      ///< the hover trim's stroke amplitude (rad)
  double phase0, phase1, phase2;  ///< random chirp phases of streams 1, 2 and 3 (rad)
  /// The zero-mean attitude excitations' fade in and out (kRampS).
  double Fade(double t) const;
};

/// The shared shapes of the paper's test-stand and free-flight presets, and what the experiments
/// beyond the paper share (60 s phases, identified at a decimated rate).
ExperimentPreset Actuator(const std::string& name, const std::string& output,
                          std::vector<std::string> inputs, double h, const std::string& h_text,
                          int mfs, const std::string& accuracy);
ExperimentPreset Attitude(const std::string& name, const std::string& output,
                          const std::string& input, double h, const std::string& h_text, int mfs,
                          const std::string& accuracy);
ExperimentPreset BeyondPaper(ExperimentPreset p, int ny, int nu, int decimate);

/// The families, each in its file, in the order Presets() lists them.
std::vector<ExperimentPreset> ActuatorPresets();
std::vector<ExperimentPreset> AttitudePresets();
std::vector<ExperimentPreset> BeyondPaperPresets();

}  // namespace odonata::experiments

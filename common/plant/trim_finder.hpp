#pragma once
// Hover trim: the flapping frequency (or stroke amplitude) at which the wing-beat mean lift of the
// level vehicle at rest equals its weight.

#include <Eigen/Core>

#include "plant/plant_config.hpp"
#include "plant/wing_command.hpp"

namespace odonata::plant {

/// Which input the trim finder solves for; the others stay at config.nominal_command.
enum class TrimVariable { kFrequency, kAmplitude };

/// Options of FindHoverTrim().
struct TrimOptions {
  TrimVariable variable{TrimVariable::kFrequency};
  int phase_samples{720};     ///< stroke-phase samples per beat for the beat mean
  double tolerance_n{1e-10};  ///< on |ΣF_z − m g|
  int max_iterations{50};
};

/// Wing-beat mean load of the whole vehicle, level and at rest.
struct MeanLoad {
  Eigen::Vector3d force_n{Eigen::Vector3d::Zero()};    ///< body frame
  Eigen::Vector3d moment_nm{Eigen::Vector3d::Zero()};  ///< about the centre of mass
  Eigen::Vector4d wing_force_z_n{Eigen::Vector4d::Zero()};
  Eigen::Vector4d wing_force_x_n{Eigen::Vector4d::Zero()};
};

/// A hover trim.
struct TrimResult {
  CommandMatrix command{CommandMatrix::Zero()};  ///< the trimmed command, same on all wings
  double freq_hz{};
  double amp_rad{};
  MeanLoad mean_load{};  ///< at the trim: force_n.z() = m g within the tolerance
  int iterations{};
};

/// Mean load over one beat of every wing, body level and at rest (the load then depends only on
/// each wing's stroke phase, sampled uniformly). Independent of the fore/hind phase offset.
/// @pre phase_samples ≥ 8.
MeanLoad ComputeMeanLoadAtRest(const PlantConfig& config, const CommandMatrix& command,
                               int phase_samples);

/// Solves ΣF_z(x) = m g for x = f or φ₀ by the fixed-point iteration x ← x √(m g / ΣF_z(x)), exact
/// in one step when lift ∝ x² (true for f at rest) and contracting otherwise.
/// @throws std::runtime_error if the trim lies outside the actuator limits or does not converge.
TrimResult FindHoverTrim(const PlantConfig& config, const TrimOptions& options = {});

}  // namespace odonata::plant

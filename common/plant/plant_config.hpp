#pragma once
// Every physical parameter of the DI-MAV plant, loaded from JSON with units in the key names.

#include <Eigen/Core>
#include <array>
#include <map>
#include <stdexcept>
#include <string>

#include "plant/wing_command.hpp"

namespace odonata::plant {

/// Raised for a configuration that cannot be read or is not physically valid. The message lists
/// every problem found, one per line, each prefixed with the file (or "config") and key.
class PlantConfigError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Rectangular, flat, rigid wing, identical for all four wings.
struct WingGeometry {
  double length_m{};           ///< root to tip along the span
  double root_offset_m{};      ///< stroke axis (hinge) to wing root along the span
  double chord_m{};            ///< constant chord
  double pitch_axis_chords{};  ///< x̂₀, pitch axis from the leading edge in chords
  int strip_count{};           ///< blade-element strips per wing (midpoint rule)
};

/// Inclusive range of each of the six per-wing inputs, in CommandIndex order and command units.
struct ActuatorLimits {
  Eigen::Matrix<double, 1, kCommandsPerWing> min{};
  Eigen::Matrix<double, 1, kCommandsPerWing> max{};
};

/// Time stepping.
struct IntegrationSettings {
  double sample_rate_hz{};   ///< output (and command hold) rate
  int min_steps_per_beat{};  ///< RK4 steps per wing beat at the highest allowed frequency
  bool rotational_forces{};  ///< include the rotational-circulation force
};

/// Horizontal ground plane in the world frame.
struct GroundSettings {
  bool enabled{};
  double height_m{};  ///< world z of the ground; the centre of mass never goes below it
};

/// What the plant does when the state diverges.
enum class DivergencePolicy { kStop, kReset };

/// Divergence limits: exceeding any of them (or a non-finite state) is a divergence.
struct DivergenceSettings {
  DivergencePolicy policy{DivergencePolicy::kStop};
  double max_tilt_rad{};    ///< on |roll| and |pitch| ("tumbling")
  double max_rate_radps{};  ///< on |ω_b|
  double max_speed_mps{};   ///< on |V_b|
};

/// The complete plant parameter set. Frames: body FLU (x forward, y left, z up, origin at the
/// centre of mass); world x, y horizontal, z up. Wing order: 1 fore-left, 2 hind-left,
/// 3 hind-right, 4 fore-right.
struct PlantConfig {
  std::string name;  ///< free text identifying the vehicle
  double mass_kg{};
  Eigen::Vector3d inertia_kgm2{};  ///< principal moments I_xx, I_yy, I_zz about body axes
  double gravity_mps2{};
  double air_density_kgpm3{};
  WingGeometry wing{};
  std::array<Eigen::Vector3d, kWingCount> hinge_position_m{};  ///< body frame, per wing
  double fore_hind_phase_rad{};  ///< stroke phase of the hind wings minus the fore wings
  Eigen::Matrix<double, 1, kCommandsPerWing> nominal_command{};  ///< f is the trim initial guess
  ActuatorLimits limits{};
  IntegrationSettings integration{};
  GroundSettings ground{};
  DivergenceSettings divergence{};
  std::map<std::string, std::string> sources;  ///< where each parameter (group) comes from

  bool operator==(const PlantConfig& other) const;
  bool operator!=(const PlantConfig& other) const { return !(*this == other); }
};

/// The 40 g parameter set of docs/plant.md §10, identical to common/plant/config/dimav_40g.json.
PlantConfig DefaultPlantConfig();

/// Parses a JSON configuration. Every key is required; unknown keys are errors (they are usually
/// typos). @param source_name used in error messages. @throws PlantConfigError listing all
/// problems.
PlantConfig ParsePlantConfig(const std::string& json_text, const std::string& source_name);

/// Reads and parses a JSON configuration file. @throws PlantConfigError (unreadable or invalid).
PlantConfig LoadPlantConfig(const std::string& path);

/// Checks physical validity; returns one line per problem (empty when valid), like isReady().
std::string ValidatePlantConfig(const PlantConfig& config);

/// Serialises to the JSON text that ParsePlantConfig reads back (round trip is exact).
std::string PlantConfigToJson(const PlantConfig& config);

/// RK4 steps per output sample: ceil(min_steps_per_beat · f_max / sample_rate), at least 1, so
/// that every allowed flapping frequency gets at least min_steps_per_beat steps per beat.
int StepsPerSample(const PlantConfig& config);

}  // namespace odonata::plant

#pragma once
// The dragonfly-inspired MAV: four blade-element wings on a 6-DOF rigid body, stepped one output
// sample (100 Hz by default) at a time with fixed-step RK4.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <array>
#include <string>
#include <vector>

#include "plant/blade_element_wing.hpp"
#include "plant/plant_config.hpp"
#include "plant/rigid_body.hpp"
#include "plant/wing_beat_averager.hpp"
#include "plant/wing_command.hpp"

namespace odonata::plant {

/// Where and how a run starts.
struct InitialCondition {
  RigidBodyState state{};  ///< t = 0 state (world position, attitude, V_b, ω_b)
  /// Test stand: the body is held at `state` and only the wing loads are computed (the actuator
  /// experiments measure forces this way, like a force balance).
  bool clamped_body{false};
  /// Command the wings were flapping with before t = 0; it fills the force-averaging history so the
  /// first samples already report wing-beat means. Zero = wings at rest.
  CommandMatrix prior_command{CommandMatrix::Zero()};
};

/// Trailing means over the vehicle's last complete wing beat: the window is 1/f̄ (f̄ the mean
/// applied flapping frequency of the four wings, capped at 0.5 s) and ends at the sample time.
/// They remove the ripple at the flapping frequency and its harmonics from the flight dynamics.
struct BeatAverages {
  double window_s{};                                           ///< averaging window 1/f̄
  Eigen::Vector3d velocity_body_mps{Eigen::Vector3d::Zero()};  ///< mean V_b
  Eigen::Vector3d rate_body_radps{Eigen::Vector3d::Zero()};    ///< mean ω_b
  double roll_rad{};   ///< mean of the continuous roll, wrapped back into (−π, π]
  double pitch_rad{};  ///< mean pitch
  double yaw_rad{};    ///< mean of the unwrapped yaw (continuous like PlantOutput::yaw_rad)
  double force_x_n{};  ///< mean total force of the four wings along body x
  double force_z_n{};  ///< mean total force of the four wings along body z
};

/// One output sample. Body frame FLU (x forward, y left, z up); world z up.
struct PlantOutput {
  double time_s{};
  Eigen::Vector3d velocity_body_mps{Eigen::Vector3d::Zero()};  ///< V_b
  Eigen::Vector3d rate_body_radps{Eigen::Vector3d::Zero()};    ///< ω_b = (p, q, r)
  double roll_rad{};                                           ///< see RollPitchYaw()
  double pitch_rad{};                                          ///< nose down > 0 (y points left)
  double yaw_rad{};                                     ///< unwrapped: continuous across ±π
  Eigen::Vector3d position_m{Eigen::Vector3d::Zero()};  ///< world frame
  Eigen::Vector4d force_x_n{Eigen::Vector4d::Zero()};   ///< per wing, wing-beat mean, body x
  Eigen::Vector4d force_z_n{Eigen::Vector4d::Zero()};   ///< per wing, wing-beat mean, body z
  bool on_ground{false};
  BeatAverages beat{};  ///< the same signals averaged over the last wing beat
};

/// Result of one Step().
enum class StepStatus {
  kOk,       ///< advanced one sample
  kReset,    ///< diverged during this sample and was reset to the initial condition
  kStopped,  ///< diverged (now or earlier) and holds its last finite state
};

/// The plant. Not thread-safe; copyable (a copy continues the same run independently).
///
/// Commands are held for one sample (zero-order hold), clamped to the configured limits. Each
/// wing's stroke phase Φ is integrated (Φ̇ = 2πf), so a change of f never makes the wing jump; hind
/// wings start fore_hind_phase_rad ahead. Within a sample, `steps_per_sample()` RK4 steps are
/// taken. After every step the ground is applied and the quaternion renormalised; after every
/// sample the state is checked for divergence, then reset or stopped as configured (never emitting
/// NaN).
class DimavPlant {
 public:
  /// @throws PlantConfigError if ValidatePlantConfig() reports problems.
  explicit DimavPlant(const PlantConfig& config);

  /// Starts a new run at t = 0 from `initial`.
  void Reset(const InitialCondition& initial);

  /// Advances one sample period with `command` (rows = wings, columns = CommandIndex).
  /// @throws std::invalid_argument if any command entry is not finite.
  StepStatus Step(const CommandMatrix& command);

  /// Instantaneous loads of all wings at given stroke phases and body motion (no state change).
  /// @param per_wing_force_n if not null, receives each wing's body-frame force (rows = wings).
  WingLoad ComputeLoads(const CommandMatrix& command, const Eigen::Vector4d& stroke_phase_rad,
                        const Eigen::Vector3d& velocity_body_mps,
                        const Eigen::Vector3d& rate_body_radps,
                        Eigen::Matrix<double, kWingCount, 3>* per_wing_force_n) const;

  /// Clamps every entry of `command` to the actuator limits.
  CommandMatrix ClampToLimits(const CommandMatrix& command) const;

  const PlantOutput& output() const { return output_; }
  const RigidBodyState& state() const { return state_; }
  const CommandMatrix& applied_command() const { return applied_command_; }
  const Eigen::Vector4d& stroke_phase_rad() const { return phase_rad_; }
  const PlantConfig& config() const { return config_; }
  double sample_period_s() const { return sample_period_s_; }
  double step_s() const { return step_s_; }
  int steps_per_sample() const { return steps_per_sample_; }
  bool stopped() const { return stopped_; }
  int reset_count() const { return reset_count_; }
  /// Description of the most recent divergence (empty if none), with its time.
  const std::string& divergence_message() const { return divergence_message_; }

 private:
  void AdvanceOneStep(const CommandMatrix& command);
  /// This step's body signals for the beat averages (angles continuous from the last sample).
  BeatVector BeatSignals(const WingForceXz& step_mean_force_n) const;
  void PrimeForceHistory(const CommandMatrix& command);
  void UpdateOutput();

  PlantConfig config_;
  RigidBody body_;
  std::vector<BladeElementWing> wings_;  // kWingCount, built once
  double sample_period_s_{};
  int steps_per_sample_{};
  double step_s_{};
  WingBeatAverager averager_;
  BeatSignalAverager beat_averager_;

  InitialCondition initial_{};
  RigidBodyState state_{};
  Eigen::Vector4d phase_rad_{Eigen::Vector4d::Zero()};
  CommandMatrix applied_command_{CommandMatrix::Zero()};
  double time_s_{};
  double previous_raw_roll_rad_{};  // roll at the last sample, and its continuous (unwrapped)
  double unwrapped_roll_rad_{};     // track: the beat average of roll is taken on it
  double previous_raw_yaw_rad_{};
  double unwrapped_yaw_rad_{};
  bool on_ground_{false};
  bool stopped_{false};
  int reset_count_{0};
  std::string divergence_message_;
  PlantOutput output_{};
};

/// Initial stroke phases: 0 for the fore wings, fore_hind_phase_rad for the hind wings.
Eigen::Vector4d InitialStrokePhases(const PlantConfig& config);

}  // namespace odonata::plant

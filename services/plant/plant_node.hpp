#pragma once
// odonata-plant's process shell: turns DIMAV_COMMAND messages into PlantSession calls and its
// answers into DIMAV_STATE messages. The plant, the onboard hold and the sequence rules live in
// the core (pipeline/plant_session.hpp).
//
// Inputs:  DIMAV_COMMAND (wing_command_t), ODONATA_CONTROL (control_t: RESET, SHUTDOWN)
// Outputs: DIMAV_STATE (plant_state_t), DIMAV_BEAT_STATE (beat_state_t, one per state, same seq),
//          ODONATA_HEARTBEAT (via BusNode)

#include <chrono>
#include <map>
#include <string>

#include "bus/bus_node.hpp"
#include "odonata/beat_state_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"
#include "pipeline/plant_session.hpp"
#include "pipeline/vehicle_setup.hpp"
#include "plant/plant_config.hpp"

namespace odonata::plant_service {

/// The service name, which control messages may address.
inline constexpr const char* kServiceName = "odonata-plant";

/// Lockstep: period of state 0 while no command has come, so a late generator finds it.
inline constexpr std::chrono::milliseconds kInitialStatePeriodMs{200};

class PlantNode {
 public:
  /// Subscribes, arms the timers and publishes state 0.
  /// @param setup_name preset whose initial condition to start from ("" = the default set-up).
  /// @throws std::invalid_argument for an unknown preset; plant::PlantConfigError for a bad
  ///         configuration.
  PlantNode(bus::BusNode& bus, const plant::PlantConfig& config, pipeline::PlantSession::Mode mode,
            const std::string& setup_name);

  const pipeline::PlantSession& session() const { return session_; }

 private:
  void OnCommand(const odonata::wing_command_t& msg);
  void OnControl(const odonata::control_t& msg);
  void Reset(const std::string& setup_name);
  // `fresh`: false for an answer sent again (its divergence was reported when it was new).
  void Publish(const pipeline::PlantSample& sample, bool fresh = true);
  /// The set-up called `name`, computed once (a preset's set-up costs a trim search).
  const pipeline::VehicleSetup& Setup(const std::string& name);

  bus::BusNode& bus_;
  plant::PlantConfig config_;
  std::map<std::string, pipeline::VehicleSetup> setups_;
  pipeline::PlantSession session_;
  bool diverged_reported_ = false;  // the heartbeat says "error" once the plant has stopped
};

}  // namespace odonata::plant_service

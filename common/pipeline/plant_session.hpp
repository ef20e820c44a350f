#pragma once
// The vehicle as a service sees it: the plant with its onboard attitude hold, answering numbered
// commands by the lockstep or real-time rules of the DIMAV_COMMAND / DIMAV_STATE protocol.
//
// Protocol: state seq k is y(k) at t_k, measured before command k is applied; command seq k is
// applied over [t_k, t_k+1); the answer to command k is state seq k + 1 with command_seq k. The
// initial state is seq 0 with command_seq -1.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "pipeline/vehicle_setup.hpp"
#include "plant/dimav_plant.hpp"
#include "plant/plant_config.hpp"
#include "sequence/lockstep_window.hpp"
#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

/// What a published state says about the vehicle (plant_state_t.status).
enum class SampleStatus {
  kOk,        ///< flying (or on the test stand)
  kOnGround,  ///< resting on the ground
  kReset,     ///< diverged during the last sample and restarted from the initial condition:
              ///< the state jumps although seq does not
  kDiverged,  ///< diverged (policy "stop"): the last finite state is held from now on
};

/// One state to publish.
struct PlantSample {
  int64_t seq{};            ///< sample index k
  int64_t command_seq{-1};  ///< the command this state answers, -1 for none (initial or trim)
  plant::PlantOutput output{};
  SampleStatus status{SampleStatus::kOk};
  /// The command the wings flapped with over [t_(seq-1), t_seq), in answer to command_seq: the
  /// received command with the onboard hold's correction added, clamped (for state 0, the
  /// command they flapped with before t = 0). Published on DIMAV_BEAT_STATE, as the hold lives
  /// in this process and the generator never sees it.
  plant::CommandMatrix applied_command{plant::CommandMatrix::Zero()};
};

/// How a submitted command was handled.
enum class CommandVerdict {
  kStepped,   ///< lockstep: the expected next command; the plant stepped (once, and once more
              ///< for every held command it released)
  kHeld,      ///< lockstep: ahead of the expected one (an earlier command is still on its
              ///< way): held until the commands before it arrive, no step
  kGap,       ///< lockstep: more than kMaxHeldCommands held: stepped over the missing ones
              ///< (`missing`) and on through the held ones
  kRepeated,  ///< lockstep: a command already applied: its answer is re-sent, no step
  kAccepted,  ///< real time: held until the next tick (may also report `missing`)
  kStale,     ///< older than (real time: or equal to) the newest command: dropped
  kRejected,  ///< not finite, outside the actuator limits, a negative seq, one that leaps
              ///< more than kMaxSeqJump ahead, or a leap of more than kConfirmLeap not yet
              ///< confirmed by a second command (sequence_window.hpp): dropped
};

/// Result of PlantSession::Submit().
struct CommandOutcome {
  CommandVerdict verdict{CommandVerdict::kRejected};
  int64_t missing{};       ///< sequence numbers skipped (before this one, or before `missing_from`)
  int64_t missing_from{};  ///< the first of them
  /// Real time, kAccepted: the command this one replaced was never applied (a tick came late and
  /// both arrived within one sample period).
  bool superseded_unapplied{false};
  /// Real time, kAccepted: how many extra samples applied the command this one replaced, because
  /// no newer command had arrived at their tick.
  int64_t extra_applications{};
  std::string problem;  ///< why it was dropped (kStale, kRejected)
  /// Lockstep: the states to publish, in order: the answer to this command and to every held
  /// command it released (kStepped, kGap), or the stored answer again (kRepeated).
  std::vector<PlantSample> publish;
};

/// The plant, its onboard stabiliser and the sequence rules. Not thread-safe.
///
/// Per step it does exactly what odonata-sim does per sample: the attitude hold (when the set-up
/// has it) acts on the output measured before the step, the result is clamped to the actuator
/// limits and held for one sample. So a lockstep run gives the same outputs, bit for bit, as
/// odonata-sim for the same commands and set-up.
///
/// Commands outside the actuator limits are rejected, not clamped: the identifier reads the
/// command from the bus, so a command the plant silently changed would teach it a response to
/// something the wings never did.
class PlantSession {
 public:
  enum class Mode { kLockstep, kRealtime };

  /// Starts at the set-up's initial condition (state 0).
  /// @throws plant::PlantConfigError for an invalid configuration.
  PlantSession(const plant::PlantConfig& config, Mode mode, VehicleSetup setup);

  /// Restarts at `setup`'s initial condition: seq restarts at 0 and every command seq is
  /// accepted again. Returns state 0.
  const PlantSample& Reset(VehicleSetup setup);

  /// Lockstep: commands held ahead of a missing one before the plant steps over the gap. A
  /// generator keeps fewer than this in flight (odonata-signal's --window ≤ 16).
  static constexpr std::size_t kMaxHeldCommands = 64;
  /// Lockstep: answers kept to re-send when their command comes again (a consumer lost one):
  /// every one a generator's resend may reach (sequence/lockstep_window.hpp).
  static constexpr std::size_t kAnswerHistory = kLockstepResendReach;

  /// Handles command `seq`.
  /// Lockstep (commands applied strictly in seq order, 0 first after a reset, so a window of
  /// commands in flight gives the same run as one at a time): the expected seq steps and answers
  /// with state seq + 1, then releases the held commands that follow it; one ahead is held; one
  /// already applied re-sends its answer without stepping (stale once it left the history); with
  /// more than kMaxHeldCommands held, the plant steps over the gap.
  /// Real time: a newer seq replaces the held command (applied at the next Tick()); the same or
  /// an older seq is stale. Replacing reports whether the old command was never applied, or
  /// applied more than once, so a loaded machine's skips and repeats are counted, not hidden.
  CommandOutcome Submit(int64_t seq, const plant::CommandMatrix& command);

  /// Real time: advances one sample with the held command (the hover trim before any command)
  /// and returns the next state. @pre mode() == Mode::kRealtime.
  const PlantSample& Tick();

  /// The most recent state (state 0 right after a reset).
  const PlantSample& last() const { return last_; }
  /// True once a command has been accepted (lockstep: applied) since the last reset.
  bool commanded() const { return newest_seq_.has_value(); }
  Mode mode() const { return mode_; }
  const VehicleSetup& setup() const { return setup_; }
  const plant::DimavPlant& plant() const { return plant_; }

 private:
  void StepWith(const plant::CommandMatrix& command, int64_t command_seq);
  // Lockstep: steps with `command` as command `seq` and records the answer.
  void StepLockstep(int64_t seq, const plant::CommandMatrix& command, CommandOutcome* out);
  // Lockstep: steps through the held commands that follow the newest applied one.
  void ReleaseHeld(CommandOutcome* out);

  Mode mode_;
  VehicleSetup setup_;
  plant::DimavPlant plant_;
  PlantSample last_{};
  std::optional<int64_t> newest_seq_;  // newest command accepted (real time), applied (lockstep)
  std::map<int64_t, plant::CommandMatrix> held_;  // lockstep: commands ahead of a missing one
  std::deque<PlantSample> answers_;               // lockstep: the latest answers, oldest first
  LeapGuard leaps_;                               // large leaps wait for a confirming command
  plant::CommandMatrix held_command_{plant::CommandMatrix::Zero()};  // real time
  int64_t held_seq_ = -1;                                            // real time
  int64_t held_applications_ = 0;  // real time: ticks that applied the held command so far
};

}  // namespace odonata::pipeline

#pragma once
// odonata-signal's process shell: sends a CommandSchedule as DIMAV_COMMAND messages, paced by the
// plant's answers (lockstep, via LockstepSequencer) or by a clock (real time).
//
// Inputs:  DIMAV_STATE (plant_state_t), ODONATA_CONTROL (control_t: SHUTDOWN); lockstep also
//          ODONATA_ACK (ack_t receipts) and ODONATA_HEARTBEAT (to discover its consumers)
// Outputs: DIMAV_COMMAND (wing_command_t), ODONATA_CONTROL (RESET to the plant),
//          ODONATA_HEARTBEAT (via BusNode)

#include <chrono>
#include <cstdint>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <boost/asio/signal_set.hpp>
#include <boost/asio/steady_timer.hpp>

#include "bus/bus_node.hpp"
#include "odonata/ack_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"
#include "pipeline/command_schedule.hpp"
#include "pipeline/lockstep_sequencer.hpp"
#include "pipeline/realtime_pacer.hpp"
#include "sequence/run_start.hpp"

namespace odonata::signal_service {

/// The service name, which control messages may address.
inline constexpr const char* kServiceName = "odonata-signal";

/// Exit code when the plant never answered (missing plant, lost link, restarted plant).
inline constexpr int kExitNoPlant = 1;
/// Exit code when the plant diverged (as odonata-sim's exit code for a stopped run).
inline constexpr int kExitDiverged = 3;
/// Exit code when a lockstep consumer stopped acknowledging or left mid-run: it misses samples.
inline constexpr int kExitConsumerLost = 4;
/// Exit code when SIGINT or SIGTERM stopped the generator before its last command: the run is
/// shorter than asked for, which a script must not take for a whole run.
inline constexpr int kExitInterrupted = 5;

/// Exit code when every command was sent in real time but the plant restarted mid-run (its
/// states began again at 0, which nobody asked for): the log holds the run in several parts.
inline constexpr int kExitPlantRestarted = 6;

/// Exit code when every command was sent but a consumer was heard whose messages this signed
/// generator refused (a service without the system's key): the run was not lossless for it.
inline constexpr int kExitConsumerRefused = 7;

/// How long a lockstep run waits for consumers landing a refit, by default: with a key, and
/// without one (where anyone can claim to be refitting).
inline constexpr double kSignedRefitWaitS = pipeline::kSignedRefitWaitSeconds;
inline constexpr double kKeylessRefitWaitS = pipeline::kKeylessRefitWaitSeconds;

/// How the generator runs.
struct SignalOptions {
  bool lockstep = true;    ///< false: real time, one command per 1/rate_hz
  double rate_hz = 100.0;  ///< real time: command rate
  int timeout_ms = 200;    ///< lockstep: resend after this long without the awaited state
  int max_resends = 10;    ///< consecutive resends before giving up
  /// Lockstep: commands in flight (1 … LockstepSequencer::kMaxWindow). The run is the same for
  /// every window; a larger one overlaps the hops of successive samples.
  int window = 16;
  bool reset_plant = true;  ///< send RESET (with the preset name) and wait for state 0 first
  std::string plant = "odonata-plant";  ///< plant instance to address and to name in errors
  /// Lockstep: consumers (instance names) whose receipt of each state the window waits for.
  std::vector<std::string> wait_for;
  /// Lockstep: listen this long before command 0 for identifier and logger heartbeats; each one
  /// heard (running or frozen) is waited for too. 0: only `wait_for`.
  double discover_s = 0;
  bool progress = false;  ///< show "sample k of N" on stderr (only for a terminal)
  /// Lockstep: send no command from this seq on until SIGUSR1, and say so on stderr once every
  /// state up to it is confirmed (-1: no hold). Tests fault a service there, at a definite sample.
  int64_t hold_at = -1;
  /// Lockstep: seconds the run waits for consumers that say they are landing a refit before it
  /// fails (< 0: 600 with a key, 45 without — on a keyless bus anyone can send "refitting").
  double refit_wait_s = -1;
  /// Lockstep with a key: a consumer heard whose messages are refused (no key, another key) ends
  /// the run at once with kExitConsumerRefused; false: warn, go on without it, and exit with that
  /// code at the end (a bus where forgers may speak, whose heartbeats look the same).
  bool refused_consumers_fail = true;
};

class SignalNode {
 public:
  /// Subscribes and starts the run (sends RESET or the first command as the mode asks). When the
  /// run ends the node stops the bus with exit code 0, kExitNoPlant or kExitDiverged.
  /// @pre schedule.size() ≥ 1, options.rate_hz > 0, options.timeout_ms > 0.
  SignalNode(bus::BusNode& bus, pipeline::CommandSchedule schedule, SignalOptions options);

  /// Commands sent, resends included.
  int64_t commands_sent() const { return commands_sent_; }
  /// Receipts (ack_t) from the consumers waited for: the confirmation hop's messages.
  int64_t receipts_received() const { return receipts_received_; }
  const pipeline::LockstepSequencer& sequencer() const { return sequencer_; }

 private:
  void OnState(const odonata::plant_state_t& msg);
  void WatchRealtimeState(const odonata::plant_state_t& msg);
  void OnAck(const odonata::ack_t& msg);
  void OnHeartbeat(const odonata::heartbeat_t& msg);
  void OnControl(const odonata::control_t& msg);
  void Apply(const pipeline::SequencerAction& action);
  void ArmTimeout();
  void WaitForTimeout();
  void StartRealtime();
  void RealtimeTick();
  void SendCommand(int64_t k);
  void SendReset();
  void ShowProgress(int64_t k, bool last);
  void AnnounceHold();
  void WaitForRelease();
  void Finish(int exit_code, const std::string& message);

  bus::BusNode& bus_;
  pipeline::CommandSchedule schedule_;
  SignalOptions options_;
  pipeline::LockstepSequencer sequencer_;
  boost::asio::steady_timer timer_;  // lockstep timeout, or real-time pacing
  boost::asio::signal_set release_;  // SIGUSR1 ends a hold (options_.hold_at)
  bool hold_announced_ = false;
  uint64_t timer_generation_ = 0;  // a handler of a superseded wait does nothing
  std::chrono::steady_clock::time_point timeout_deadline_{};  // lockstep: resend after this
  bool timeout_armed_ = false;
  bool realtime_started_ = false;
  pipeline::RealtimePacer pacer_;  // real time: when each command is due
  int64_t next_realtime_ = 0;
  int64_t commands_sent_ = 0;
  int64_t states_received_ = 0;    // answers from the plant, resent ones included
  int64_t receipts_received_ = 0;  // ack_t from the consumers waited for
  int64_t control_seq_ = 0;
  bool finished_ = false;
  std::string consumer_left_;     // a consumer that stopped mid-run (the run failed it)
  pipeline::RunStart plant_run_;  // real time: the plant's states, for a restart
  int64_t plant_restarts_ = 0;
  int64_t first_restart_command_ = -1;  // the command being sent when the first was seen
  std::optional<std::chrono::steady_clock::time_point> first_command_;  // lockstep rate
  std::chrono::steady_clock::time_point last_progress_{};
  std::set<std::string> refused_consumers_;  // consumers heard but refused (no or another key)
};

}  // namespace odonata::signal_service

#pragma once
// odonata-replay's process shell: publishes a recorded flight (FlightRows) as signals_t on
// VEHICLE_SIGNALS, so the live identifier, monitor and logger run on it exactly as next to the
// vehicle: at the flight's own pace (speed 1), faster, or in lockstep with the receipts of the
// identifiers and loggers (VEHICLE_SIGNALS_ACK), as fast as the slowest learns, nothing lost.
//
// Inputs:  VEHICLE_SIGNALS_ACK (ack_t), ODONATA_HEARTBEAT (lockstep: to discover consumers)
// Outputs: VEHICLE_SIGNALS (signals_t)

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bus/bus_node.hpp"
#include "pipeline/realtime_pacer.hpp"
#include "replay/flight_rows.hpp"
#include "replay/lockstep_receipts.hpp"
#include "sequence/lockstep_window.hpp"
#include "sequence/refit_patience.hpp"

namespace odonata::replay {

/// Exit code when a lockstep consumer stopped acknowledging: it would miss samples.
inline constexpr int kExitConsumerLost = 4;
/// Exit code when SIGINT or SIGTERM stopped the replay before its last sample.
inline constexpr int kExitInterrupted = 5;

struct ReplayOptions {
  bool lockstep = false;
  double speed = 1.0;  ///< not lockstep: the flight's time runs this many times faster
  std::string source;  ///< signals_t.source (the vehicle's name)
  /// Lockstep: consumers whose receipt of each sample the next one waits for.
  std::vector<std::string> wait_for;
  /// Lockstep: seconds to listen for identifier and logger heartbeats first; each one heard is
  /// waited for too (0: only wait_for).
  double discover_s = pipeline::kLockstepDiscoverySeconds;
  int timeout_ms = 200;   ///< lockstep: resend a sample after this long without every receipt
  int max_resends = 100;  ///< lockstep: resends of one sample before giving up on a consumer
  /// Lockstep: how long to wait for consumers landing a scheduled refit (heartbeat "refitting"),
  /// whose timeouts resend nothing and cost none of max_resends; < 0: 600 s on a signed bus, 45 s
  /// on a keyless one (sequence/refit_patience.hpp).
  double refit_wait_s = -1;
  double progress_s = 5;  ///< seconds between progress lines on stderr (0: none)
};

class ReplayNode {
 public:
  ReplayNode(bus::BusNode& bus, FlightRows flight, ReplayOptions options);
  /// What was sent: file, samples, rows skipped, seconds, mode, consumers, resends.
  nlohmann::json Summary() const;
  std::string SummaryLine() const;
  bool finished() const { return finished_; }

 private:
  void Begin();
  // Real time: sends row `row` and schedules the next at its time.
  void SendPaced(std::size_t row);
  // Lockstep: sends the next complete row after `row` − 1 and waits for its receipts.
  void SendLockstep(std::size_t row);
  void Publish(std::size_t row);
  void ArmResend(std::size_t row, int64_t generation);
  void Finish(int exit_code);
  void Progress(std::size_t row);
  // The next row holding every value (a row with a gap is not sent), or rows() when none.
  std::size_t NextComplete(std::size_t row);

  bus::BusNode& bus_;
  FlightRows flight_;
  ReplayOptions options_;
  LockstepReceipts receipts_;
  bool started_ = false, finished_ = false;
  std::chrono::steady_clock::time_point start_, last_progress_;
  pipeline::RealtimePacer pacer_;  // paced: when each row is due
  std::chrono::steady_clock::time_point end_;
  int64_t sent_ = 0;  // samples published (resends not counted)
  int64_t resends_ = 0;
  int64_t skipped_ = 0;      // rows with a missing value, not sent
  int64_t newest_seq_ = -1;  // the newest seq published
  int64_t awaited_ = -1;     // lockstep: the seq whose receipts are awaited
  int64_t generation_ = 0;   // lockstep: invalidates a resend timer once its sample is held
  int resends_of_awaited_ = 0;
  pipeline::RefitPatience patience_{0};  // lockstep: consumers landing a refit
};

}  // namespace odonata::replay

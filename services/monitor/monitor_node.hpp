#pragma once
// odonata-monitor: scores the identifier's predictions live, watches every service's
// heartbeat, and keeps the last model snapshot of each identifier so a restarted one resumes.
//
// Inputs:  ODONATA_PREDICTION, ODONATA_HEARTBEAT, ODONATA_MODEL, ODONATA_CONTROL
// Outputs: ODONATA_ACCURACY (accuracy_t), ODONATA_MODEL (cached snapshot, on request),
//          the terminal table, an optional JSON summary on exit.

#include <chrono>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "bus/bus_node.hpp"
#include "monitoring/peer_table.hpp"
#include "monitoring/prediction_scoreboard.hpp"
#include "odonata/accuracy_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/heartbeat_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/prediction_t.hpp"

namespace odonata::monitor {

struct MonitorOptions {
  /// How predictions are scored: the window, the warning level, the change alarm and the margin
  /// over the live ARX (one home for them and their defaults: monitoring::ScoreboardOptions).
  monitoring::ScoreboardOptions scoring;
  double publish_hz = 2.0;           ///< accuracy_t rate
  double print_period_s = 5.0;       ///< terminal line period when stdout is not a terminal
  double heartbeat_timeout_s = 3.0;  ///< warn when a service is silent this long
  std::string summary_json;          ///< write final accuracy here on exit (optional)
  bool live_table = false;           ///< redraw a table (stdout is a terminal)
};

class MonitorNode {
 public:
  MonitorNode(bus::BusNode& bus, MonitorOptions options);

  /// Final accuracy per output (what --summary-json writes).
  nlohmann::json Summary() const;

  /// Bounds on what the monitor remembers from the bus, so a flood of forged heartbeats or
  /// snapshots cannot grow it without limit: past them, the least recently heard is forgotten.
  static constexpr std::size_t kMaxPeers = monitoring::PeerTable::kMaxPeers;
  static constexpr std::size_t kMaxSnapshots = 64;
  /// And in bytes (their encoded size, which the decoded message about matches in memory): 16
  /// forged snapshots of 14 MB each must not hold 700 MB.
  static constexpr std::size_t kMaxSnapshotBytes = 64u << 20;
  std::size_t snapshot_bytes() const { return snapshot_bytes_; }
  static constexpr std::size_t kMaxFinishedRuns =
      monitoring::PredictionScoreboard::kMaxFinishedRuns;
  std::size_t peer_count() const { return peers_.peers().size(); }
  std::size_t snapshot_count() const { return snapshots_.size(); }

  /// True while `output`'s window FIT is below warn_fit_percent (a warning was printed and the
  /// FIT has not recovered since).
  bool Warned(const std::string& output) const { return scores_.Warned(output); }
  /// True while `output`'s change alarm is raised (accuracy fell well below its settled level
  /// and has not come back).
  bool Alarmed(const std::string& output) const { return scores_.Alarmed(output); }
  /// True while `output`'s fuzzy model has not beaten the identifier's live ARX over the last
  /// window (one step ahead): the table marks it "<= ARX".
  bool BehindArx(const std::string& output) const { return scores_.BehindArx(output); }

 private:
  void OnPrediction(const odonata::prediction_t& msg);
  void OnHeartbeat(const odonata::heartbeat_t& msg);
  void OnSnapshot(const odonata::model_snapshot_t& msg);
  void OnControl(const odonata::control_t& msg);
  void PublishAccuracy();
  void CheckPeers();
  void Print();

  bus::BusNode& bus_;
  MonitorOptions options_;
  monitoring::PredictionScoreboard scores_;
  monitoring::PeerTable peers_;
  struct CachedSnapshot {
    odonata::model_snapshot_t snapshot;
    std::chrono::steady_clock::time_point received;
    std::size_t bytes = 0;
  };
  std::size_t snapshot_bytes_ = 0;
  std::map<std::string, CachedSnapshot> snapshots_;  // last per identifier instance
  int64_t accuracy_seq_ = 0;
  std::size_t printed_lines_ = 0;
};

}  // namespace odonata::monitor

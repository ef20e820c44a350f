#pragma once
// odonata-identifier's process shell: turns command and state messages into samples for the
// OnlineIdentifier core and publishes what it says. All learning lives in the core.
//
// Inputs:  DIMAV_COMMAND (wing_command_t), DIMAV_STATE (plant_state_t), DIMAV_BEAT_STATE
//          (beat_state_t, only when the model uses a beat average or an applied-command
//          channel), ODONATA_CONTROL (control_t), ODONATA_MODEL (model_snapshot_t, only to resume)
// Which messages make sample k, and how: SampleStream (sample_stream.hpp).
// Outputs: ODONATA_PREDICTION (prediction_t, one per sample), ODONATA_MODEL (periodic and on
//          request), ODONATA_HEARTBEAT (via BusNode)

#include <deque>
#include <optional>
#include <string>
#include <vector>

#include "bus/ack_publisher.hpp"
#include "bus/bus_node.hpp"
#include "identifier_config/identifier_config.hpp"
#include "odonata/beat_state_t.hpp"
#include "odonata/control_t.hpp"
#include "odonata/model_snapshot_t.hpp"
#include "odonata/plant_state_t.hpp"
#include "odonata/wing_command_t.hpp"
#include "sample_stream.hpp"
#include "sysid/online/online_identifier.hpp"

namespace odonata::identifier {

/// Exit code of a run in which a prediction was not finite (the model diverged and was restored).
inline constexpr int kExitDiverged = 3;

/// The longest a landing waits for its refit before giving up on it (the refit cancelled, the
/// model kept, the refit counted as failed with the reason): a refit starved of CPU must not hold
/// the identifier, its heartbeat "refitting", for ever (docs/guide/live-system.md).
inline constexpr int kRefitWaitBoundS = 600;

class IdentifierNode {
 public:
  /// @param initial a saved model to start from; without one the node first asks the bus for
  ///        the last snapshot of its instance (for resume_wait_s), then starts empty.
  IdentifierNode(bus::BusNode& bus, IdentifierConfig config,
                 std::optional<sysid::NarxModel> initial, std::string save_model_path,
                 std::string models_dir = "");

  const sysid::OnlineIdentifier& core() const { return core_; }

 private:
  /// Back to the state before "refitting", once a landing that had to wait is done.
  void RefitLanded();
  void OnCommand(const odonata::wing_command_t& msg);
  void OnState(const odonata::plant_state_t& msg);
  void OnBeatState(const odonata::beat_state_t& msg);
  void OnControl(const odonata::control_t& msg);
  /// Carries out a command addressed to this identifier; returns what was done.
  /// @throws std::exception when it cannot (the reply says why).
  std::string Obey(const odonata::control_t& msg);
  /// The live parameters every reply carries (and GET asks for).
  std::vector<std::pair<std::string, double>> Parameters() const;
  void OnSnapshot(const odonata::model_snapshot_t& msg);
  void StartLearning(const std::string& how);
  void Handle(const std::vector<SampleStream::Event>& events);
  // Publishes the lockstep receipt (ack_t): after every state (a resend's too, so a lost receipt
  // is repaired), else only when it advanced.
  void Acknowledge(int64_t state_seq = -1);
  // The receipt of signals_t samples on the signals_ack channel (odonata-replay --lockstep):
  // `seq` is the sample just handled, answered even when it was a resend.
  void AcknowledgeSignals(int64_t seq = -1);
  void Learn(const sysid::Sample& sample);
  /// At the stop: the samples heard, taken, lost and not learned, adding up to the newest seq.
  void PrintSampleAccounting() const;
  /// Judges whether the model has seen enough (identifier_settling.cpp): every kSettlingEvery
  /// samples learned, or now (a GET, a freeze, a new model).
  enum class SettlingJudgement { kWhenDue, kNow };
  void ReportSettling(SettlingJudgement when);
  static constexpr int64_t kSettlingEvery = 100;
  int64_t settling_judged_at_ = 0;
  std::vector<int> settling_said_;  ///< per output, the SettlingState last printed (−1: none)
  std::vector<int> settling_;       ///< per output, the SettlingState last judged
  void PublishSnapshot();
  // A non-finite prediction at `sample`: error state, exit code, the last good model back.
  void Diverged(int64_t sample);
  // The model as it is, when it predicts finitely: what a divergence falls back to.
  void KeepLastGood();
  void SaveModel(const std::string& path);
  sysid::NarxModel EmptyModel() const;
  bus::BusNode& bus_;
  IdentifierConfig config_;
  std::string save_model_path_;
  std::string models_dir_;  // where SAVE_MODEL with a file name writes ("" = refused)
  bus::AckPublisher acks_;
  bus::AckPublisher signal_acks_;
  sysid::OnlineIdentifier core_;
  const void* snapshots_ = nullptr;  // the subscription to snapshots, dropped once started
  bool started_ = false;             // false while waiting for a snapshot to resume from
  SampleStream stream_;              // pairing, the model's signals, decimation (config_.decimate)
  // What came in while it waited for a snapshot, in order: learned once it starts (from the
  // snapshot, or empty), so a flight's first second (its take-off) is not lost. Bounded: beyond
  // kMostWaiting the oldest go, each counted as not learned.
  std::deque<SampleStream::Event> waiting_;
  static constexpr std::size_t kMostWaiting = 100000;  // 1000 s at 100 Hz
  int64_t resumed_through_ = -1;  // the snapshot resumed had learned through this seq
  int64_t samples_taken_ = 0;     // samples handed to the learner (learned, or filling its lags)
  int64_t not_learned_ = 0;       // samples that came in and were never learned (the bound above)
  int64_t prediction_seq_ = 0;
  int64_t already_learned_ = 0;      ///< samples refused as learned before a resume, as last said
  int64_t missed_on_resume_ = 0;     ///< samples missed while down, as last said
  int64_t refits_reported_ = 0;      ///< refits landed or failed, as last said on stderr
  int64_t incumbents_reported_ = 0;  ///< of them, those that kept the last refit's model
  int64_t refused_reported_ = 0;     ///< of them, steady-state models refused (SteadyStateHolds)
  int64_t linear_reported_ = 0;      ///< of them, linear models landed (LinearWinsTheNewSamples)
  int64_t experts_reported_ = 0;     ///< of them, those that kept the rules it started from
  bool expert_replaced_reported_ = false;
  std::string state_before_refit_;  ///< the heartbeat state to go back to after "refitting"
  std::chrono::steady_clock::time_point refit_wait_began_;
  /// Called while a landing waits for its refit (identifier_refit_wait.cpp).
  sysid::RefitWait WhileRefitting();
  int64_t snapshot_seq_ = 0;
  // The last model that predicted finitely (KeepLastGood), and the divergences since start.
  std::optional<sysid::NarxModel> last_good_;
  int64_t last_good_learned_ = 0;
  int64_t diverged_ = 0;
  // Why the newest vehicle message was refused (empty once one is taken again), and how many
  // were: a configuration naming a signal the vehicle does not send must not look like a quiet
  // run (the heartbeat's state and GET's answer say it).
  std::string input_problem_;
  int64_t inputs_refused_ = 0;
  void OnSignals(const odonata::signals_t& msg);
};

}  // namespace odonata::identifier

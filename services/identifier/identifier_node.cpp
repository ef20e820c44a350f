#include "identifier_node.hpp"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

#include "io/atomic_file.hpp"
#include "model_messages/model_snapshot_message.hpp"
#include "model_messages/prediction_message.hpp"
#include "odonata/prediction_t.hpp"
#include "snapshot_admission.hpp"

namespace odonata::identifier {

namespace {

// A saved model names its format near its start (NarxModel::ToJson); a log or a configuration
// does not.
bool LooksLikeSavedModel(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(4096, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  return head.find("\"odonata-narx-fuzzy\"") != std::string::npos;
}

}  // namespace

IdentifierNode::IdentifierNode(bus::BusNode& bus, IdentifierConfig config,
                               std::optional<sysid::NarxModel> initial, std::string save_model_path,
                               std::string models_dir)
    : bus_(bus),
      config_(std::move(config)),
      save_model_path_(std::move(save_model_path)),
      models_dir_(std::move(models_dir)),
      acks_(bus, config_.channels.ack),
      signal_acks_(bus, config_.channels.signals_ack),
      core_(initial ? *initial : EmptyModel(), config_.refit),
      stream_(core_.model().spec(), config_.decimate) {
  core_.set_max_gap(config_.max_gap);
  // Refits that choose K steps ahead are scored so live too: every prediction carries ŷ(k | k−K).
  if (config_.refit.horizon >= 2) core_.set_ahead_horizon(config_.refit.horizon);
  // A model given at start is an expert's: refits refine its rules, and replace them only when
  // their own choice beats them (docs/identifier.md §6.3).
  if (initial) core_.KeepExpertRules();
  // Samples are formed from the first message on; while it waits for a snapshot they are kept.
  stream_.Start();
  // A landing that must wait for its refit blocks this thread: WhileRefitting says so and beats
  // (a generator that starts during the wait hears a consumer that will read again).
  core_.SetRefitWaitHook([this] { return WhileRefitting(); },
                         std::chrono::milliseconds(std::max<int64_t>(
                             1, static_cast<int64_t>(bus_.options().heartbeat_period_s * 1e3))));
  const auto& ch = config_.channels;
  if (config_.source == SampleSource::kSignals) {
    // Any vehicle, one signals_t per sample: no pairing, and no lockstep receipts (odonata's
    // generator is not driving it).
    bus_.Subscribe<odonata::signals_t>(ch.signals, [this](const auto& m) { OnSignals(m); });
  } else {
    bus_.Subscribe<odonata::wing_command_t>(ch.command, [this](const auto& m) { OnCommand(m); });
    bus_.Subscribe<odonata::plant_state_t>(ch.state, [this](const auto& m) { OnState(m); });
    if (stream_.needs_beat_states()) {
      bus_.Subscribe<odonata::beat_state_t>(ch.beat_state,
                                            [this](const auto& m) { OnBeatState(m); });
    }
  }
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
  snapshots_ =
      bus_.Subscribe<odonata::model_snapshot_t>(ch.model, [this](const auto& m) { OnSnapshot(m); });
  if (initial || config_.resume_wait_s <= 0) {
    StartLearning(initial ? "from the saved model" : "with an empty model");
  } else {
    bus_.SetState("waiting");
    odonata::control_t ask{};
    ask.utime = bus::NowUtime();
    ask.target = config_.instance;
    ask.command = odonata::control_t::PUBLISH_SNAPSHOT;
    bus_.Publish(ch.control, ask);
    bus_.After(std::chrono::microseconds(static_cast<int64_t>(config_.resume_wait_s * 1e6)),
               [this] {
                 if (!started_)
                   StartLearning("with an empty model (no snapshot of '" + config_.instance +
                                 "' on the bus)");
               });
  }
  if (config_.snapshot_period_s > 0) {
    bus_.Every(std::chrono::microseconds(static_cast<int64_t>(config_.snapshot_period_s * 1e6)),
               [this] {
                 if (started_) PublishSnapshot();
               });
  }
  bus_.OnShutdown([this] {
    PrintSampleAccounting();
    if (started_) PublishSnapshot();  // the next instance resumes from exactly here
    if (!save_model_path_.empty()) SaveModel(save_model_path_);
  });
}

sysid::NarxModel IdentifierNode::EmptyModel() const {
  sysid::NarxModel m(config_.spec, config_.model);
  m.SetScaling(sysid::ScalingFromRanges(config_.spec, config_.ranges));
  return m;
}

void IdentifierNode::StartLearning(const std::string& how) {
  started_ = true;
  // Snapshots only matter while it waits to resume: from now on the kernel drops them, and with
  // them every fragment on the group (bus_node.hpp, kMayBeFragmented), so a flood of large
  // snapshots costs the sample loop nothing.
  bus_.Unsubscribe(snapshots_);
  KeepLastGood();  // what a divergence before the first snapshot falls back to
  bus_.SetState(core_.learning() ? "running" : "frozen");
  std::fprintf(stderr, "[%s] learning %s (%d rules)%s\n", config_.instance.c_str(), how.c_str(),
               core_.model().total_rules(),
               waiting_.empty() ? ""
                                : (", then the " + std::to_string(waiting_.size()) +
                                   " messages' samples that came in while it waited")
                                      .c_str());
  // What came in while it waited follows the snapshot's samples (or starts an empty model): the
  // vehicle's first samples, learned in order before anything newer.
  const std::vector<SampleStream::Event> held(waiting_.begin(), waiting_.end());
  waiting_.clear();
  Handle(held);
  Acknowledge();  // a lockstep generator waiting on them hears that they are held
  AcknowledgeSignals();
}

void IdentifierNode::OnSnapshot(const odonata::model_snapshot_t& msg) {
  if (started_ || msg.instance != config_.instance) return;
  const std::string mismatch = SnapshotMismatch(msg, config_);
  if (!mismatch.empty()) {
    ++bus_.stats().dropped;
    bus_.stats().last_error = "snapshot not resumed: " + mismatch;
    StartLearning("with an empty model: the snapshot of '" + msg.instance +
                  "' on the bus does not fit this identifier (" + mismatch + ")");
    return;
  }
  sysid::NarxModel model =
      model_messages::DecodeSnapshot(msg);  // throws on a malformed snapshot: counted
  if (msg.samples_learned < 0) throw std::invalid_argument("snapshot with a negative sample count");
  core_.ReplaceModel(std::move(model), msg.samples_learned,
                     std::max<int64_t>(-1, msg.learned_through));
  resumed_through_ = std::max<int64_t>(-1, msg.learned_through);
  if (msg.learning == 0) core_.Freeze();  // frozen before it stopped: frozen again
  StartLearning(
      "from the bus snapshot after " + std::to_string(msg.samples_learned) + " learned samples" +
      (msg.learned_through >= 0 ? " (through sample " + std::to_string(msg.learned_through) +
                                      "; earlier samples of this run are not learned again)"
                                : std::string()) +
      (msg.learning == 0 ? " (frozen, as it was)" : ""));
}

// The receipt goes out after learning: a receipt for a sample this process had not yet learned
// and predicted would, after a kill -9 in between, cost one sample more than the resume
// accounting of docs/lcm.md §10 allows.
void IdentifierNode::OnCommand(const odonata::wing_command_t& msg) {
  Handle(stream_.OnCommand(msg));
  Acknowledge();
}

void IdentifierNode::OnState(const odonata::plant_state_t& msg) {
  Handle(stream_.OnState(msg));
  Acknowledge(msg.seq);
}

void IdentifierNode::OnBeatState(const odonata::beat_state_t& msg) {
  Handle(stream_.OnBeat(msg));
  Acknowledge();
}

void IdentifierNode::Acknowledge(int64_t state_seq) {
  // Waiting for a snapshot, samples are kept but not yet learned: no receipt, so a lockstep
  // generator does not count this identifier as having them (a kill meanwhile would lose them).
  // StartLearning acknowledges them once learned.
  if (started_) acks_.Publish(stream_.newest_held_state(), state_seq);
}

void IdentifierNode::AcknowledgeSignals(int64_t seq) {
  if (started_ && config_.source == SampleSource::kSignals)
    signal_acks_.Publish(stream_.newest_signals(), seq);
}

void IdentifierNode::OnSignals(const odonata::signals_t& msg) {
  // The newest sample again: a lockstep replay resending it because its receipt was lost (or
  // sent before this identifier had started). Answered, neither learned twice nor counted.
  if (msg.seq >= 0 && msg.seq == stream_.newest_signals()) {
    AcknowledgeSignals(msg.seq);
    return;
  }
  std::vector<SampleStream::Event> events;
  try {
    events = stream_.OnSignals(msg);
  } catch (const std::invalid_argument& e) {
    ++inputs_refused_;
    const bool first = input_problem_.empty();
    input_problem_ = e.what();
    if (first && started_) bus_.SetState("refusing input: " + input_problem_);
    throw;  // the bus counts it as dropped and reports it
  }
  if (!input_problem_.empty()) {
    input_problem_.clear();
    if (started_) bus_.SetState(core_.learning() ? "running" : "frozen");
  }
  Handle(events);
  AcknowledgeSignals(msg.seq);
}

void IdentifierNode::Handle(const std::vector<SampleStream::Event>& events) {
  if (!started_) {
    for (const auto& e : events) {
      if (waiting_.size() == kMostWaiting) {
        if (waiting_.front().kind == SampleStream::Event::Kind::kSample) ++not_learned_;
        waiting_.pop_front();
        bus_.stats().last_error = std::to_string(not_learned_) +
                                  " samples not learned: more came in while waiting for a "
                                  "snapshot than it keeps";
      }
      waiting_.push_back(e);
    }
    return;
  }
  for (const auto& e : events) {
    switch (e.kind) {
      case SampleStream::Event::Kind::kRestart:
        core_.RestartHistory();
        break;
      case SampleStream::Event::Kind::kGap:
        bus_.stats().gaps += e.lost;
        bus_.Report(e.what, e.message);
        break;
      case SampleStream::Event::Kind::kSample:
        Learn(e.sample);
        break;
    }
  }
}

void IdentifierNode::Learn(const sysid::Sample& sample) {
  ++samples_taken_;
  sysid::PushResult result;
  const auto report = core_.Push(sample, &result);
  RefitLanded();
  if (result == sysid::PushResult::kGap || result == sysid::PushResult::kBridged)
    bus_.stats().gaps = std::max(bus_.stats().gaps, core_.gaps());
  if (core_.missed_on_resume() > missed_on_resume_) {
    const int64_t missed = core_.missed_on_resume() - missed_on_resume_;
    missed_on_resume_ = core_.missed_on_resume();
    bus_.Report("samples missed on resume",
                std::to_string(missed) + " samples before sample " + std::to_string(sample.index) +
                    " were not learned: the identifier was down, or learned them after its last "
                    "snapshot and lost them with it (counted as gaps)");
  }
  if (result == sysid::PushResult::kRejected || result == sysid::PushResult::kDuplicate) {
    ++bus_.stats().dropped;
    if (result == sysid::PushResult::kDuplicate && core_.already_learned() > already_learned_) {
      already_learned_ = core_.already_learned();
      bus_.Report("sample already learned",
                  "sample " + std::to_string(sample.index) +
                      " is at or before the newest the resumed snapshot had learned (" +
                      std::to_string(core_.already_learned()) +
                      " refused so far: resent or replayed traffic of this run)");
    }
    return;
  }
  if (!report) return;
  if (core_.refits() + core_.failed_refits() != refits_reported_) {
    // A scheduled refit landed (docs/identifier.md §6.3): say so, it replaced the model.
    refits_reported_ = core_.refits() + core_.failed_refits();
    // Frozen, it is the refit that closed learning, noticed at the next sample scored (its own
    // landing count is the last sample learned).
    const std::string when = core_.learning() ? "landed at sample " + std::to_string(sample.index)
                                              : "(the one that closed learning, after " +
                                                    std::to_string(core_.samples_learned()) +
                                                    " samples learned) landed";
    // A refit that kept the last refit's model says so: its selection lost on the newest samples.
    const bool kept = core_.incumbents_kept() != incumbents_reported_;
    incumbents_reported_ = core_.incumbents_kept();
    // A steady-state refit whose model failed its checks says so, and what took its place.
    const bool refused = core_.steady_state_refused() != refused_reported_;
    refused_reported_ = core_.steady_state_refused();
    std::string why;
    if (refused)
      why = kept ? ", the last refit's model kept (the steady-state model ran away or did not "
                   "come to rest)"
                 : ", chosen again (the steady-state model ran away or did not come to rest)";
    else if (kept)
      why = ", the last refit's model kept (it predicts the newest samples better)";
    // The rules the identifier started from: kept (refined) or replaced, said each time.
    if (core_.experts_kept() != experts_reported_) {
      experts_reported_ = core_.experts_kept();
      why +=
          ", the rules it started from kept, their consequents refined (the refit's own choice "
          "did not beat them on its hold-out by the margin)";
    }
    if (core_.expert_replaced() && !expert_replaced_reported_) {
      expert_replaced_reported_ = true;
      why +=
          ", the rules it started from replaced (the refit's own choice beat them on its "
          "hold-out by the margin)";
    }
    // A refit whose fuzzy model lost to the linear one on the samples since it began.
    const bool linear = core_.linear_landed() != linear_reported_;
    linear_reported_ = core_.linear_landed();
    if (linear)
      why +=
          ", the linear model landed (it beat the fuzzy one on the samples since the refit "
          "began)";
    std::fprintf(stderr, "%s: refit %lld %s: %d rules%s %s\n", config_.instance.c_str(),
                 static_cast<long long>(core_.refits()), when.c_str(), core_.model().total_rules(),
                 why.c_str(), core_.FailedRefitsText().c_str());
  }
  if (!report->predicted.allFinite()) return Diverged(sample.index);
  bus_.Publish(config_.channels.prediction,
               model_messages::ToPredictionMessage(*report, core_.model().spec().outputs,
                                                   prediction_seq_++, bus::NowUtime()));
  ReportSettling(SettlingJudgement::kWhenDue);
  if (config_.snapshot_every_samples > 0 && report->learned &&
      core_.samples_learned() % config_.snapshot_every_samples == 0) {
    PublishSnapshot();
  }
}

void IdentifierNode::OnControl(const odonata::control_t& msg) {
  if (!bus_.AcceptControl(msg)) return;
  // Its own resume request (PUBLISH_SNAPSHOT to itself at start) needs no answer.
  const bool own = msg.sender == config_.instance;
  std::string done;
  try {
    done = Obey(msg);
  } catch (const std::exception& e) {
    // A value out of range, an unwritable file: the operator learns why, the model is unchanged.
    ++bus_.stats().dropped;
    bus_.stats().last_error = bus::ControlCommandName(msg.command) + ": " + e.what();
    std::fprintf(stderr, "[%s] rejected %s from '%s': %s\n", config_.instance.c_str(),
                 bus::ControlCommandName(msg.command).c_str(), msg.sender.c_str(), e.what());
    if (!own) bus_.ReplyControl(msg, false, e.what(), Parameters());
    return;
  }
  if (!own) bus_.ReplyControl(msg, true, done, Parameters());
  if (msg.command == odonata::control_t::SHUTDOWN) bus_.Stop(0);
}

std::string IdentifierNode::Obey(const odonata::control_t& msg) {
  switch (msg.command) {
    case odonata::control_t::FREEZE:
      core_.Freeze();
      if (started_ && input_problem_.empty()) bus_.SetState("frozen");
      // A freeze before anything was learned is obeyed, but not in silence: the model it keeps
      // predicting with is empty (a vehicle that never reached it, a wrong channel or name).
      if (core_.model().total_rules() == 0)
        return "frozen with an empty model: no sample learned yet (" +
               std::to_string(core_.samples_learned()) +
               " samples); check that the vehicle's samples reach it (get, the heartbeat)";
      return "frozen: predicting, not learning";
    case odonata::control_t::RESUME:
      core_.Resume();
      RefitLanded();
      if (started_ && input_problem_.empty()) bus_.SetState("running");
      return "learning";
    case odonata::control_t::RESET:
      std::fprintf(stderr, "[%s] reset by '%s': the model (%d rules, %lld samples) is discarded\n",
                   config_.instance.c_str(), msg.sender.c_str(), core_.model().total_rules(),
                   static_cast<long long>(core_.samples_learned()));
      core_.ReplaceModel(EmptyModel());
      return "model discarded";
    case odonata::control_t::SET_ENTROPY_THRESHOLD:
      core_.SetEntropyThreshold(msg.value);  // the fuzzy core checks the range
      return "entropy threshold set";
    case odonata::control_t::SET_FORGETTING:
      core_.SetForgetting(msg.value);
      return "forgetting factor set";
    case odonata::control_t::SAVE_MODEL: {
      // Asked for a model that holds nothing, the operator hears so rather than getting a file
      // with no rule (--save-model at shutdown still writes what there is).
      if (core_.model().total_rules() == 0)
        throw std::invalid_argument("the model is empty (" +
                                    std::to_string(core_.samples_learned()) +
                                    " samples learned): nothing to save yet");
      // A name from the bus: only a plain file name, written inside --models-dir.
      const std::string path =
          msg.path.empty() ? save_model_path_ : io::ConfinedPath(models_dir_, msg.path);
      // A models directory of its own (odonata-run's models/, the board's
      // /var/lib/odonata/models) may not exist yet before the first named save.
      if (!msg.path.empty()) std::filesystem::create_directories(models_dir_);
      // The models directory may be a run's folder: a name from the bus never replaces a file
      // that is not a saved model (the live event log, the configuration a restart reads).
      if (!msg.path.empty() &&
          std::filesystem::is_regular_file(std::filesystem::symlink_status(path)) &&
          !LooksLikeSavedModel(path))
        throw std::invalid_argument("save-model would replace " + path +
                                    ", which is not a saved model");
      SaveModel(path);
      return "model saved to " + path;
    }
    case odonata::control_t::PUBLISH_SNAPSHOT:
      // Our own resume request is answered by others; answer theirs only when running.
      if (started_) PublishSnapshot();
      return started_ ? "snapshot published" : "starting: no snapshot yet";
    case odonata::control_t::SHUTDOWN:
      // Stops after the answer is out (OnControl).
      return "stopping (the model is saved on the way out when --save-model is set)";
    case odonata::control_t::GET:
      // A run that refuses every sample answers with why, not with "accepted".
      if (!input_problem_.empty())
        throw std::invalid_argument("input refused (" + std::to_string(inputs_refused_) +
                                    " messages): " + input_problem_);
      ReportSettling(SettlingJudgement::kNow);
      return "parameters in force; seen enough? " + bus_.stats().detail;
    default:
      throw std::invalid_argument("unknown control command " + std::to_string(msg.command));
  }
}

std::vector<std::pair<std::string, double>> IdentifierNode::Parameters() const {
  const auto& m = core_.model();
  const auto& cfg = m.model(0).config();
  auto p = std::vector<std::pair<std::string, double>>{
      {"entropy_threshold", cfg.entropy.threshold},
      {"forgetting", cfg.forgetting},
      {"learning", core_.learning() ? 1.0 : 0.0},
      {"rules", static_cast<double>(m.total_rules())},
      {"max_rules", static_cast<double>(cfg.entropy.max_rules)},
      {"samples_learned", static_cast<double>(core_.samples_learned())},
      {"gaps", static_cast<double>(core_.gaps())},
      {"bridged", static_cast<double>(core_.bridged())},
      {"not_learned", static_cast<double>(not_learned_)},
      // Refused after a resume: the snapshot had learned them (a resend or a replay).
      {"already_learned", static_cast<double>(core_.already_learned())},
      // The rules it started from (a .fis or model file): refits that kept them, refined, and
      // whether one replaced them.
      {"expert_rules_kept", static_cast<double>(core_.experts_kept())},
      {"expert_rules_replaced", core_.expert_replaced() ? 1.0 : 0.0},
      // Predictions made outside the data the model was trained on (docs/identifier.md §7.3).
      {"samples_predicted", static_cast<double>(core_.samples_predicted())},
      {"samples_outside", static_cast<double>(core_.samples_outside())},
      // Predictions that were not finite: each restored the last good model (Diverged).
      {"diverged", static_cast<double>(diverged_)}};
  // Per output, whether the model has seen enough: 0 short of excitation, 1 still learning,
  // 2 settled (SettlingWatch; the sentences are in GET's reason and the heartbeat's detail).
  for (std::size_t o = 0; o < settling_.size() && o < m.spec().outputs.size(); ++o)
    p.emplace_back("seen_enough." + m.spec().outputs[o], settling_[o]);
  return p;
}

void IdentifierNode::RefitLanded() {
  if (bus_.state() == "refitting") bus_.SetState(state_before_refit_);
}

void IdentifierNode::Diverged(int64_t sample) {
  // A prediction that is not finite (inputs far beyond any range, a learner that ran away) is an
  // error the heartbeat, the log and the exit code carry; the model goes back to the last good
  // one, so the run goes on predicting instead of publishing NaN.
  ++diverged_;
  bus_.SetExitCode(kExitDiverged);
  std::string how =
      "the last good model (" + std::to_string(last_good_learned_) + " samples learned) restored";
  if (last_good_)
    core_.ReplaceModel(*last_good_, last_good_learned_);
  else
    how = "no good model to restore";
  bus_.SetState("error: a prediction was not finite at sample " + std::to_string(sample) + "; " +
                how);
  bus_.Report("model diverged", "a prediction was not finite at sample " + std::to_string(sample) +
                                    ": " + how + " (the run will exit " +
                                    std::to_string(kExitDiverged) + ")");
}

void IdentifierNode::KeepLastGood() {
  if (!core_.model().Readable()) return;
  last_good_ = core_.model();
  last_good_learned_ = core_.samples_learned();
}

void IdentifierNode::PublishSnapshot() {
  core_.Settle();  // a closing refit after a freeze is the model to publish (waits for it)
  RefitLanded();
  KeepLastGood();
  odonata::model_snapshot_t s = model_messages::EncodeSnapshot(core_.model());
  s.utime = bus::NowUtime();
  s.seq = snapshot_seq_++;
  s.samples_learned = core_.samples_learned();
  s.learned_through = core_.learned_through();
  s.learning = core_.learning() ? 1 : 0;
  s.instance = config_.instance;
  bus_.Publish(config_.channels.model, s);
}

}  // namespace odonata::identifier

#include "identifier_node.hpp"

#include <cstdio>
#include <stdexcept>

#include "experiments/sample_columns.hpp"
#include "io/atomic_file.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"
#include "model_messages/model_snapshot_message.hpp"
#include "model_messages/prediction_message.hpp"
#include "odonata/prediction_t.hpp"
#include "snapshot_admission.hpp"

namespace odonata::identifier {
namespace {
// The model's signals: outputs, then inputs (the order of a decimated row).
std::vector<std::string> SpecSignals(const sysid::RegressorSpec& spec) {
  std::vector<std::string> names = spec.outputs;
  names.insert(names.end(), spec.inputs.begin(), spec.inputs.end());
  return names;
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
      core_(initial ? *initial : EmptyModel()),
      pairer_(messages::PairingNeedsOf(SpecSignals(core_.model().spec()))),
      decimator_(config_.decimate, AveragedSignals(core_.model().spec())) {
  const auto& ch = config_.channels;
  bus_.Subscribe<odonata::wing_command_t>(ch.command, [this](const auto& m) { OnCommand(m); });
  bus_.Subscribe<odonata::plant_state_t>(ch.state, [this](const auto& m) { OnState(m); });
  if (pairer_.needs().beat || pairer_.needs().next_beat) {
    bus_.Subscribe<odonata::beat_state_t>(ch.beat_state, [this](const auto& m) { OnBeatState(m); });
  }
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
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
  bus_.SetState(core_.learning() ? "running" : "frozen");
  std::fprintf(stderr, "[%s] learning %s (%d rules)\n", config_.instance.c_str(), how.c_str(),
               core_.model().total_rules());
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
  core_.ReplaceModel(std::move(model), msg.samples_learned);
  if (msg.learning == 0) core_.Freeze();  // frozen before it stopped: frozen again
  StartLearning("from the bus snapshot after " + std::to_string(msg.samples_learned) +
                " learned samples" + (msg.learning == 0 ? " (frozen, as it was)" : ""));
}

void IdentifierNode::OnCommand(const odonata::wing_command_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("command with NaN or Inf fields");
  const std::string count = messages::CountProblems(msg);
  if (!count.empty()) throw std::invalid_argument("command: " + count);
  Handle(pairer_.OnCommand(msg));
  Acknowledge(false);
}

void IdentifierNode::OnState(const odonata::plant_state_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("state with NaN or Inf fields");
  Handle(pairer_.OnState(msg));
  Acknowledge(true);
}

void IdentifierNode::OnBeatState(const odonata::beat_state_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("beat state with NaN or Inf fields");
  Handle(pairer_.OnBeat(msg));
  Acknowledge(false);
}

void IdentifierNode::Acknowledge(bool always) {
  // Waiting for a snapshot, samples are not learned: no receipt, so a lockstep generator does not
  // count this identifier as having them.
  if (started_) acks_.Publish(pairer_.newest_held_state(), always);
}

void IdentifierNode::Handle(std::vector<Pairer::Event> events) {
  for (const auto& e : events) {
    switch (e.kind) {
      case Pairer::Event::Kind::kRestart:
        core_.RestartHistory();
        decimator_.Reset();
        break;
      case Pairer::Event::Kind::kGap:
        bus_.stats().gaps += e.lost;
        bus_.Report(e.what, e.message);
        break;
      case Pairer::Event::Kind::kSample:
        if (started_) FormSample(e);
        break;
    }
  }
}

std::vector<bool> IdentifierNode::AveragedSignals(const sysid::RegressorSpec& spec) {
  std::vector<bool> averaged;
  for (const auto& name : SpecSignals(spec))
    averaged.push_back(experiments::IsAveragedSignal(name));
  return averaged;
}

void IdentifierNode::FormSample(const Pairer::Event& paired) {
  const auto& spec = core_.model().spec();
  sysid::Sample sample;
  sample.index = paired.index;
  sample.outputs.resize(static_cast<Eigen::Index>(spec.outputs.size()));
  sample.inputs.resize(static_cast<Eigen::Index>(spec.inputs.size()));
  for (std::size_t o = 0; o < spec.outputs.size(); ++o) {
    const auto v = messages::PairedSignal(paired, spec.outputs[o]);
    if (!v) throw std::invalid_argument("the state has no signal '" + spec.outputs[o] + "'");
    sample.outputs(static_cast<Eigen::Index>(o)) = *v;
  }
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    const auto v = messages::PairedSignal(paired, spec.inputs[i]);
    if (!v) throw std::invalid_argument("no command or state signal '" + spec.inputs[i] + "'");
    sample.inputs(static_cast<Eigen::Index>(i)) = *v;
  }
  if (decimator_.factor() > 1) {
    // Learn from the block's sample, indexed by block: the model runs at the decimated rate.
    std::vector<double> row(sample.outputs.data(), sample.outputs.data() + sample.outputs.size());
    row.insert(row.end(), sample.inputs.data(), sample.inputs.data() + sample.inputs.size());
    const auto block = decimator_.Push(sample.index, row);
    if (!block) return;
    const auto no = sample.outputs.size();
    for (Eigen::Index o = 0; o < no; ++o) sample.outputs(o) = (*block)[static_cast<std::size_t>(o)];
    for (Eigen::Index i = 0; i < sample.inputs.size(); ++i)
      sample.inputs(i) = (*block)[static_cast<std::size_t>(no + i)];
    sample.index /= decimator_.factor();
  }
  sysid::PushResult result;
  const auto report = core_.Push(sample, &result);
  if (result == sysid::PushResult::kGap)
    bus_.stats().gaps = std::max(bus_.stats().gaps, core_.gaps());
  if (result == sysid::PushResult::kRejected || result == sysid::PushResult::kDuplicate) {
    ++bus_.stats().dropped;
    return;
  }
  if (!report) return;
  const odonata::prediction_t p = model_messages::ToPredictionMessage(
      *report, spec.outputs, prediction_seq_++, bus::NowUtime());
  bus_.Publish(config_.channels.prediction, p);
  if (config_.snapshot_every_samples > 0 && report->learned &&
      core_.samples_learned() % config_.snapshot_every_samples == 0) {
    PublishSnapshot();
  }
}

void IdentifierNode::OnControl(const odonata::control_t& msg) {
  if (!bus_.AcceptControl(msg)) return;
  switch (msg.command) {
    case odonata::control_t::FREEZE:
      core_.Freeze();
      if (started_) bus_.SetState("frozen");
      break;
    case odonata::control_t::RESUME:
      core_.Resume();
      if (started_) bus_.SetState("running");
      break;
    case odonata::control_t::RESET:
      std::fprintf(stderr, "[%s] reset by '%s': the model (%d rules, %lld samples) is discarded\n",
                   config_.instance.c_str(), msg.sender.c_str(), core_.model().total_rules(),
                   static_cast<long long>(core_.samples_learned()));
      core_.ReplaceModel(EmptyModel());
      break;
    case odonata::control_t::SET_ENTROPY_THRESHOLD:
      core_.SetEntropyThreshold(msg.value);  // the fuzzy core checks the range
      break;
    case odonata::control_t::SET_FORGETTING:
      core_.SetForgetting(msg.value);
      break;
    case odonata::control_t::SAVE_MODEL:
      if (msg.path.empty()) {
        SaveModel(save_model_path_);
        break;
      }
      // A name from the bus: only a plain file name, written inside --models-dir.
      try {
        SaveModel(io::ConfinedPath(models_dir_, msg.path));
      } catch (const std::invalid_argument& e) {
        ++bus_.stats().dropped;
        bus_.stats().last_error = std::string("refused save-model: ") + e.what();
        std::fprintf(stderr, "[%s] refused save-model '%s' from '%s': %s\n",
                     config_.instance.c_str(), msg.path.c_str(), msg.sender.c_str(), e.what());
      }
      break;
    case odonata::control_t::PUBLISH_SNAPSHOT:
      // Our own resume request is answered by others; answer theirs only when running.
      if (started_) PublishSnapshot();
      break;
    case odonata::control_t::SHUTDOWN:
      bus_.Stop(0);
      break;
    default:
      throw std::invalid_argument("unknown control command " + std::to_string(msg.command));
  }
}

void IdentifierNode::PublishSnapshot() {
  odonata::model_snapshot_t s = model_messages::EncodeSnapshot(core_.model());
  s.utime = bus::NowUtime();
  s.seq = snapshot_seq_++;
  s.samples_learned = core_.samples_learned();
  s.learning = core_.learning() ? 1 : 0;
  s.instance = config_.instance;
  bus_.Publish(config_.channels.model, s);
}

void IdentifierNode::SaveModel(const std::string& path) {
  if (path.empty()) throw std::invalid_argument("SAVE_MODEL without a path (and no --save-model)");
  core_.model().Save(path);
  std::fprintf(stderr, "[%s] model saved to %s (%d rules, %lld samples learned)\n",
               config_.instance.c_str(), path.c_str(), core_.model().total_rules(),
               static_cast<long long>(core_.samples_learned()));
}

}  // namespace odonata::identifier

#include "identifier_node.hpp"

#include <cstdio>
#include <stdexcept>

#include "bus/model_snapshot_codec.hpp"
#include "bus/sample_fields.hpp"
#include "odonata/prediction_t.hpp"
#include "pipeline/sequence_window.hpp"

namespace odonata::identifier {
namespace {
constexpr std::size_t kMaxCommands = 4096;     // commands kept for pairing with states
constexpr std::size_t kMaxPendingStates = 64;  // states waiting for a command before giving up
}  // namespace

IdentifierNode::IdentifierNode(bus::BusNode& bus, IdentifierConfig config,
                               std::optional<sysid::NarxModel> initial, std::string save_model_path)
    : bus_(bus),
      config_(std::move(config)),
      save_model_path_(std::move(save_model_path)),
      core_(initial ? *initial : EmptyModel()) {
  const auto& ch = config_.channels;
  bus_.Subscribe<odonata::wing_command_t>(ch.command, [this](const auto& m) { OnCommand(m); });
  bus_.Subscribe<odonata::plant_state_t>(ch.state, [this](const auto& m) { OnState(m); });
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
  core_.ReplaceModel(bus::DecodeSnapshot(msg));  // throws on a malformed snapshot: counted
  StartLearning("from the bus snapshot of sample " + std::to_string(msg.samples_learned));
}

void IdentifierNode::OnCommand(const odonata::wing_command_t& msg) {
  if (!bus::AllFinite(msg)) throw std::invalid_argument("command with NaN or Inf fields");
  const std::string count = bus::CountProblems(msg);
  if (!count.empty()) throw std::invalid_argument("command: " + count);
  const int64_t newest_command = commands_.empty() ? -1 : commands_.rbegin()->first;
  if (!pipeline::SeqWithinWindow(msg.seq, newest_command))
    throw std::invalid_argument("command seq " + std::to_string(msg.seq) +
                                " is negative or leaps past the newest, " +
                                std::to_string(newest_command));
  // A generator that restarted counts from 0 again: forget the old run's commands.
  if (!commands_.empty() && msg.seq + static_cast<int64_t>(kMaxCommands) < newest_command)
    commands_.clear();
  // The first command of a seq wins: a resend carries the same values, and a later message
  // reusing the seq (a stale or forged one) must not change a sample after the fact.
  if (!commands_.emplace(msg.seq, msg).second) {
    if (msg.source == commands_.at(msg.seq).source) return;  // a lockstep resend: not a problem
    throw std::invalid_argument("a second command with seq " + std::to_string(msg.seq) + " from '" +
                                msg.source + "'");
  }
  while (commands_.size() > kMaxCommands) commands_.erase(commands_.begin());
  Process();
}

void IdentifierNode::OnState(const odonata::plant_state_t& msg) {
  if (!bus::AllFinite(msg)) throw std::invalid_argument("state with NaN or Inf fields");
  const int64_t newest = !pending_states_.empty() ? pending_states_.back().seq
                         : previous_state_        ? previous_state_->seq
                                                  : -1;
  if (!pipeline::SeqWithinWindow(msg.seq, newest))
    throw std::invalid_argument("state seq " + std::to_string(msg.seq) +
                                " is negative or leaps past the newest, " + std::to_string(newest));
  if (newest >= 0 && msg.seq <= newest) {
    if (msg.seq == 0 && msg.command_seq < 0 && newest > 0) {  // the plant restarted its run
      previous_state_.reset();
      pending_states_.clear();
      commands_.clear();
      core_.RestartHistory();
    } else if (msg.seq == newest) {
      return;  // the plant re-published its latest state (lockstep resend, or waiting at 0)
    } else {
      throw std::invalid_argument("duplicate or out-of-order state seq " + std::to_string(msg.seq));
    }
  }
  pending_states_.push_back(msg);
  Process();
}

void IdentifierNode::Process() {
  while (!pending_states_.empty()) {
    const odonata::plant_state_t s = pending_states_.front();
    if (!previous_state_ || s.seq != previous_state_->seq + 1) {
      if (previous_state_ && s.seq > previous_state_->seq + 1) {
        bus_.stats().gaps += s.seq - previous_state_->seq - 1;
        bus_.Report("gap in states", "missing state seq " +
                                         std::to_string(previous_state_->seq + 1) + " … " +
                                         std::to_string(s.seq - 1));
      }
      previous_state_ = s;
      pending_states_.pop_front();
      continue;
    }
    const auto cmd = commands_.find(s.command_seq);
    if (cmd == commands_.end()) {
      if (pending_states_.size() < kMaxPendingStates) return;  // the command may still come
      ++bus_.stats().gaps;
      bus_.Report("missing command", "no command seq " + std::to_string(s.command_seq) +
                                         " for state seq " + std::to_string(s.seq));
      previous_state_ = s;
      pending_states_.pop_front();
      continue;
    }
    if (started_) FormSample(*previous_state_, cmd->second);
    previous_state_ = s;
    pending_states_.pop_front();
  }
}

void IdentifierNode::FormSample(const odonata::plant_state_t& state,
                                const odonata::wing_command_t& command) {
  const auto& spec = core_.model().spec();
  sysid::Sample sample;
  sample.index = state.seq;
  sample.outputs.resize(static_cast<Eigen::Index>(spec.outputs.size()));
  sample.inputs.resize(static_cast<Eigen::Index>(spec.inputs.size()));
  for (std::size_t o = 0; o < spec.outputs.size(); ++o) {
    const auto v = bus::StateField(state, spec.outputs[o]);
    if (!v) throw std::invalid_argument("the state has no signal '" + spec.outputs[o] + "'");
    sample.outputs(static_cast<Eigen::Index>(o)) = *v;
  }
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    auto v = bus::CommandField(command, spec.inputs[i]);
    if (!v) v = bus::StateField(state, spec.inputs[i]);
    if (!v) throw std::invalid_argument("no command or state signal '" + spec.inputs[i] + "'");
    sample.inputs(static_cast<Eigen::Index>(i)) = *v;
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
  odonata::prediction_t p;
  p.utime = bus::NowUtime();
  p.seq = prediction_seq_++;
  p.sample = report->index;
  p.num_outputs = static_cast<int32_t>(spec.outputs.size());
  p.names = spec.outputs;
  for (Eigen::Index o = 0; o < report->measured.size(); ++o) {
    p.measured.push_back(report->measured(o));
    p.predicted.push_back(report->predicted(o));
    p.free_run.push_back(report->free_run(o));
    p.next.push_back(report->next(o));
    p.rules.push_back(report->rules(o));
    p.max_entropy.push_back(report->max_entropy(o));
  }
  p.learning = report->learned ? 1 : 0;
  bus_.Publish(config_.channels.prediction, p);
  if (config_.snapshot_every_samples > 0 && report->learned &&
      core_.samples_learned() % config_.snapshot_every_samples == 0) {
    PublishSnapshot();
  }
}

void IdentifierNode::OnControl(const odonata::control_t& msg) {
  if (!msg.target.empty() && msg.target != config_.instance && msg.target != bus_.options().service)
    return;
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
      core_.ReplaceModel(EmptyModel());
      break;
    case odonata::control_t::SET_ENTROPY_THRESHOLD:
      core_.SetEntropyThreshold(msg.value);  // the fuzzy core checks the range
      break;
    case odonata::control_t::SET_FORGETTING:
      core_.SetForgetting(msg.value);
      break;
    case odonata::control_t::SAVE_MODEL:
      SaveModel(msg.path.empty() ? save_model_path_ : msg.path);
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
  odonata::model_snapshot_t s = bus::EncodeSnapshot(core_.model());
  s.utime = bus::NowUtime();
  s.seq = snapshot_seq_++;
  s.samples_learned = core_.samples_learned();
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

#include "sample_stream.hpp"

#include <cmath>
#include <stdexcept>

#include "experiments/sample_columns.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/signals_message.hpp"
#include "messages/wing_command_message.hpp"

namespace odonata::identifier {
namespace {
// The model's signals: outputs, then inputs (the order of a decimated row).
std::vector<std::string> Signals(const sysid::RegressorSpec& spec) {
  std::vector<std::string> names = spec.outputs;
  names.insert(names.end(), spec.inputs.begin(), spec.inputs.end());
  return names;
}

std::vector<bool> AveragedSignals(const sysid::RegressorSpec& spec) {
  std::vector<bool> averaged;
  for (const auto& name : Signals(spec)) averaged.push_back(experiments::IsAveragedSignal(name));
  return averaged;
}
}  // namespace

SampleStream::SampleStream(sysid::RegressorSpec spec, int decimate)
    : spec_(std::move(spec)),
      pairer_(messages::PairingNeedsOf(Signals(spec_))),
      decimator_(decimate, AveragedSignals(spec_)) {}

std::vector<SampleStream::Event> SampleStream::OnCommand(const odonata::wing_command_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("command with NaN or Inf fields");
  const std::string count = messages::CountProblems(msg);
  if (!count.empty()) throw std::invalid_argument("command: " + count);
  return Form(pairer_.OnCommand(msg));
}

std::vector<SampleStream::Event> SampleStream::OnState(const odonata::plant_state_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("state with NaN or Inf fields");
  std::vector<Event> events = Form(pairer_.OnState(msg));
  // The first state is a run's very first: its samples are new, whatever a resumed model had
  // learned of an earlier run (the pairer sees no restart, having no earlier state).
  if (!state_seen_ && msg.seq == 0 && msg.command_seq < 0)
    events.insert(events.begin(), RunBegins());
  state_seen_ = true;
  return events;
}

SampleStream::Event SampleStream::RunBegins() {
  decimator_.Reset();  // a block never spans two runs
  Event e;
  e.kind = Event::Kind::kRestart;
  return e;
}

std::vector<SampleStream::Event> SampleStream::OnBeat(const odonata::beat_state_t& msg) {
  if (!messages::AllFinite(msg)) throw std::invalid_argument("beat state with NaN or Inf fields");
  return Form(pairer_.OnBeat(msg));
}

std::vector<SampleStream::Event> SampleStream::OnSignals(const odonata::signals_t& msg) {
  const std::string problems = messages::SignalsProblems(msg);
  if (!problems.empty()) throw std::invalid_argument(problems);
  std::vector<Event> events;
  const auto verdict = signals_sequence_.Next(msg.seq);
  using Kind = pipeline::SampleSequence::Verdict::Kind;
  if (verdict.kind == Kind::kDrop) throw std::invalid_argument("signals " + verdict.why);
  // A first seq 0 begins a run, as a state 0 does (RunBegins).
  const bool run_begins = !signals_seen_ && msg.seq == 0;
  signals_seen_ = true;
  if (verdict.kind == Kind::kRestart || run_begins) {
    // The model's history restarts, as for a restarted plant.
    events.push_back(RunBegins());
  } else if (verdict.lost > 0) {
    Event e;
    e.kind = Event::Kind::kGap;
    e.lost = verdict.lost;
    e.what = "gap";
    e.message = std::to_string(e.lost) + " signals samples lost before seq " +
                std::to_string(msg.seq) + " (from '" + msg.source + "')";
    events.push_back(std::move(e));
  }
  if (!started_) return events;
  Event e;
  e.sample.index = msg.seq;
  e.sample.outputs.resize(static_cast<Eigen::Index>(spec_.outputs.size()));
  e.sample.inputs.resize(static_cast<Eigen::Index>(spec_.inputs.size()));
  const auto read = [&msg](const std::string& name) {
    const auto v = messages::SignalValue(msg, name);
    if (!v) {
      std::string have;
      for (int i = 0; i < msg.num_signals && i < 20; ++i)
        have += (i ? ", " : "") + msg.names[static_cast<std::size_t>(i)];
      if (msg.num_signals > 20) have += ", …";
      throw std::invalid_argument("signals from '" + msg.source + "' have no '" + name +
                                  "' (they have " + have + "): check the configuration's names");
    }
    if (!std::isfinite(*v))
      throw std::invalid_argument("signals from '" + msg.source + "': '" + name +
                                  "' is not finite");
    return *v;
  };
  for (std::size_t o = 0; o < spec_.outputs.size(); ++o)
    e.sample.outputs(static_cast<Eigen::Index>(o)) = read(spec_.outputs[o]);
  for (std::size_t i = 0; i < spec_.inputs.size(); ++i)
    e.sample.inputs(static_cast<Eigen::Index>(i)) = read(spec_.inputs[i]);
  if (Decimate(&e.sample)) events.push_back(std::move(e));
  return events;
}

std::vector<SampleStream::Event> SampleStream::Form(
    const std::vector<messages::PairedMessages>& paired) {
  using Paired = messages::PairedMessages;
  std::vector<Event> events;
  for (const auto& p : paired) {
    Event e;
    switch (p.kind) {
      case Paired::Kind::kRestart:
        events.push_back(RunBegins());
        break;
      case Paired::Kind::kGap:
        e.kind = Event::Kind::kGap;
        e.lost = p.lost;
        e.what = p.what;
        e.message = p.message;
        events.push_back(std::move(e));
        break;
      case Paired::Kind::kSample:
        if (started_ && FormSample(p, &e.sample)) events.push_back(std::move(e));
        break;
    }
  }
  return events;
}

bool SampleStream::FormSample(const messages::PairedMessages& paired, sysid::Sample* sample) {
  sample->index = paired.index;
  sample->outputs.resize(static_cast<Eigen::Index>(spec_.outputs.size()));
  sample->inputs.resize(static_cast<Eigen::Index>(spec_.inputs.size()));
  for (std::size_t o = 0; o < spec_.outputs.size(); ++o) {
    const auto v = messages::PairedSignal(paired, spec_.outputs[o]);
    if (!v) throw std::invalid_argument("the state has no signal '" + spec_.outputs[o] + "'");
    sample->outputs(static_cast<Eigen::Index>(o)) = *v;
  }
  for (std::size_t i = 0; i < spec_.inputs.size(); ++i) {
    const auto v = messages::PairedSignal(paired, spec_.inputs[i]);
    if (!v) throw std::invalid_argument("no command or state signal '" + spec_.inputs[i] + "'");
    sample->inputs(static_cast<Eigen::Index>(i)) = *v;
  }
  return Decimate(sample);
}

bool SampleStream::Decimate(sysid::Sample* sample) {
  if (decimator_.factor() == 1) return true;
  // Learn from the block's sample, indexed by block: the model runs at the decimated rate.
  std::vector<double> row(sample->outputs.data(), sample->outputs.data() + sample->outputs.size());
  row.insert(row.end(), sample->inputs.data(), sample->inputs.data() + sample->inputs.size());
  const auto block = decimator_.Push(sample->index, row);
  if (!block) return false;
  const auto no = sample->outputs.size();
  for (Eigen::Index o = 0; o < no; ++o) sample->outputs(o) = (*block)[static_cast<std::size_t>(o)];
  for (Eigen::Index i = 0; i < sample->inputs.size(); ++i)
    sample->inputs(i) = (*block)[static_cast<std::size_t>(no + i)];
  sample->index /= decimator_.factor();
  return true;
}

}  // namespace odonata::identifier

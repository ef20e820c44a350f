#include "plant_node.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"

namespace odonata::plant_service {
namespace {
std::string SetupKey(const std::string& name) { return name.empty() ? "default" : name; }
}  // namespace

PlantNode::PlantNode(bus::BusNode& bus, const plant::PlantConfig& config,
                     pipeline::PlantSession::Mode mode, const std::string& setup_name)
    : bus_(bus), config_(config), session_(config_, mode, Setup(setup_name)) {
  const auto& ch = bus_.channels();
  bus_.Subscribe<odonata::wing_command_t>(ch.command, [this](const auto& m) { OnCommand(m); });
  bus_.Subscribe<odonata::control_t>(ch.control, [this](const auto& m) { OnControl(m); });
  if (mode == pipeline::PlantSession::Mode::kLockstep) {
    bus_.Every(kInitialStatePeriodMs, [this] {
      if (!session_.commanded()) Publish(session_.last());
    });
  } else {
    const auto period = std::chrono::microseconds(
        static_cast<int64_t>(1e6 / config_.integration.sample_rate_hz + 0.5));
    bus_.Every(period, [this] { Publish(session_.Tick()); });
  }
  bus_.SetState(mode == pipeline::PlantSession::Mode::kLockstep ? "waiting" : "running");
  Publish(session_.last());
}

const pipeline::VehicleSetup& PlantNode::Setup(const std::string& name) {
  const std::string key = SetupKey(name);
  auto it = setups_.find(key);
  if (it == setups_.end()) {
    it = setups_.emplace(key, pipeline::VehicleSetupByName(key, config_)).first;
  }
  return it->second;
}

void PlantNode::OnCommand(const odonata::wing_command_t& msg) {
  // Thrown errors are counted as dropped and reported once per kind by BusNode.
  if (!messages::AllFinite(msg)) throw std::invalid_argument("command with NaN or Inf fields");
  const std::string count = messages::CountProblems(msg);
  if (!count.empty()) throw std::invalid_argument("command: " + count);

  const pipeline::CommandOutcome out = session_.Submit(msg.seq, messages::ToCommandMatrix(msg));
  switch (out.verdict) {
    case pipeline::CommandVerdict::kRejected:
      ++bus_.stats().dropped;
      bus_.Report("command rejected", out.problem);
      return;
    case pipeline::CommandVerdict::kStale:
      ++bus_.stats().dropped;
      bus_.Report("stale command", out.problem);
      return;
    default:
      break;
  }
  if (out.missing > 0) {
    bus_.stats().gaps += out.missing;
    bus_.Report("gap in commands", "missing command seq " + std::to_string(out.missing_from) +
                                       " … " + std::to_string(out.missing_from + out.missing - 1));
  }
  if (out.superseded_unapplied) {
    ++bus_.stats().skipped;
    bus_.Report("command never applied",
                "command seq " + std::to_string(msg.seq - 1 - out.missing) +
                    " was replaced before a sample applied it (the sample clock fell behind)");
  }
  bus_.stats().repeated += out.extra_applications;
  if (session_.mode() == pipeline::PlantSession::Mode::kLockstep) bus_.SetState("running");
  const bool fresh = out.verdict != pipeline::CommandVerdict::kRepeated;
  for (const pipeline::PlantSample& sample : out.publish) Publish(sample, fresh);
}

void PlantNode::OnControl(const odonata::control_t& msg) {
  if (!bus_.AcceptControl(msg)) return;
  const bool lockstep = session_.mode() == pipeline::PlantSession::Mode::kLockstep;
  const auto params = [&] {
    return std::vector<std::pair<std::string, double>>{
        {"lockstep", lockstep ? 1.0 : 0.0}, {"commanded", session_.commanded() ? 1.0 : 0.0}};
  };
  switch (msg.command) {
    case odonata::control_t::RESET:
      try {
        Reset(msg.path.empty() ? session_.setup().name : msg.path);
      } catch (const std::exception& e) {
        bus_.ReplyControl(msg, false, e.what(), params());
        throw;  // counted and reported as before
      }
      bus_.ReplyControl(msg, true, "reset to " + session_.setup().name, params());
      break;
    case odonata::control_t::SHUTDOWN:
      bus_.ReplyControl(msg, true, "stopping", params());
      bus_.Stop(0);
      break;
    case odonata::control_t::GET:
      bus_.ReplyControl(msg, true, "set-up " + session_.setup().name, params());
      break;
    default:
      bus_.RejectUnsupported(msg);  // the identifier's commands (freeze, save, …)
      break;
  }
}

void PlantNode::Reset(const std::string& setup_name) {
  const pipeline::VehicleSetup& setup = Setup(setup_name);  // throws for an unknown preset
  session_.Reset(setup);
  diverged_reported_ = false;
  std::fprintf(stderr, "[%s] reset to the initial condition of %s\n",
               bus_.options().instance.c_str(), setup.name.c_str());
  if (std::isfinite(setup.damage.at_s)) {
    std::fprintf(stderr,
                 "[%s] this run damages the vehicle: from t = %.3g s wing %s flies %.3g of the "
                 "commanded stroke amplitude and %.3g of the frequency\n",
                 bus_.options().instance.c_str(), setup.damage.at_s,
                 setup.damage.wing == 0 ? "every" : std::to_string(setup.damage.wing).c_str(),
                 setup.damage.amplitude_scale, setup.damage.frequency_scale);
  }
  bus_.SetState(session_.mode() == pipeline::PlantSession::Mode::kLockstep ? "waiting" : "running");
  Publish(session_.last());
}

void PlantNode::Publish(const pipeline::PlantSample& sample, bool fresh) {
  if (!fresh) {
    // An answer sent again: reported when it was new.
  } else if (sample.status == pipeline::SampleStatus::kReset) {
    bus_.Report("plant diverged and reset", session_.plant().divergence_message());
  } else if (sample.status == pipeline::SampleStatus::kDiverged && !diverged_reported_) {
    diverged_reported_ = true;
    bus_.Report("plant diverged and stopped", session_.plant().divergence_message());
    bus_.SetState("error");
  }
  const int64_t now = bus::NowUtime();
  // Beside it, never instead of it: consumers of DIMAV_STATE are untouched. Together, so the
  // consumers woken by the state do not hold up its beat state.
  bus_.PublishTogether(bus_.channels().state, messages::ToStateMessage(sample, now),
                       bus_.channels().beat_state,
                       messages::ToBeatStateMessage(sample, session_.setup(), now));
}

}  // namespace odonata::plant_service

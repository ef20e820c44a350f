#include "pipeline/plant_session.hpp"

#include <algorithm>
#include <cmath>
#include "contract/precondition.hpp"

#include "experiments/vehicle_step.hpp"
#include "pipeline/command_limits.hpp"
#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {
namespace {

bool Finite(const plant::PlantOutput& o) {
  const plant::BeatAverages& b = o.beat;
  return std::isfinite(o.time_s) && o.velocity_body_mps.allFinite() &&
         o.rate_body_radps.allFinite() && std::isfinite(o.roll_rad) && std::isfinite(o.pitch_rad) &&
         std::isfinite(o.yaw_rad) && o.position_m.allFinite() && o.force_x_n.allFinite() &&
         o.force_z_n.allFinite() && std::isfinite(b.window_s) && b.velocity_body_mps.allFinite() &&
         b.rate_body_radps.allFinite() && std::isfinite(b.roll_rad) && std::isfinite(b.pitch_rad) &&
         std::isfinite(b.yaw_rad) && std::isfinite(b.force_x_n) && std::isfinite(b.force_z_n);
}

SampleStatus StatusOf(const plant::PlantOutput& o) {
  return o.on_ground ? SampleStatus::kOnGround : SampleStatus::kOk;
}

}  // namespace

PlantSession::PlantSession(const plant::PlantConfig& config, Mode mode, VehicleSetup setup)
    : mode_(mode), plant_(config) {
  Reset(std::move(setup));
}

const PlantSample& PlantSession::Reset(VehicleSetup setup) {
  setup_ = std::move(setup);
  plant_.Reset(setup_.initial);
  newest_seq_.reset();
  leaps_ = LeapGuard{};
  held_command_ = setup_.trim_command;
  held_seq_ = -1;
  held_applications_ = 0;
  last_ = PlantSample{0, -1, plant_.output(), StatusOf(plant_.output()), plant_.applied_command()};
  return last_;
}

void PlantSession::StepWith(const plant::CommandMatrix& command, int64_t command_seq) {
  const double t_s = static_cast<double>(last_.seq) / plant_.config().integration.sample_rate_hz;
  const experiments::VehicleStep step = experiments::StepVehicle(
      plant_, command, setup_.attitude_hold, setup_.hold_gains, setup_.damage, t_s);
  const plant::StepStatus status = step.status;
  const plant::CommandMatrix& applied = step.applied;
  PlantSample next{last_.seq + 1, command_seq, plant_.output(), StatusOf(plant_.output()), applied};
  if (status == plant::StepStatus::kReset) next.status = SampleStatus::kReset;
  if (status == plant::StepStatus::kStopped) next.status = SampleStatus::kDiverged;
  if (!Finite(next.output)) {
    // DimavPlant promises never to emit NaN; should it ever, hold the last finite state rather
    // than put NaN on the bus.
    next.output = last_.output;
    next.status = SampleStatus::kDiverged;
  }
  last_ = next;
}

CommandOutcome PlantSession::Submit(int64_t seq, const plant::CommandMatrix& command) {
  CommandOutcome out;
  out.problem = leaps_.Problem("command", seq, newest_seq_.value_or(-1));
  if (!out.problem.empty()) return out;  // kRejected
  out.problem = CommandLimitProblems(command, plant_.config().limits);
  if (!out.problem.empty()) return out;  // kRejected

  if (newest_seq_ && seq < *newest_seq_ + (mode_ == Mode::kLockstep ? 0 : 1)) {
    out.verdict = CommandVerdict::kStale;
    out.problem =
        "command seq " + std::to_string(seq) + " is older than " +
        (mode_ == Mode::kLockstep ? "the last one applied, " : "or equal to the newest, ") +
        std::to_string(*newest_seq_);
    return out;
  }
  if (mode_ == Mode::kLockstep && newest_seq_ && seq == *newest_seq_) {
    // The generator lost our answer and resent the command: answer again, do not step twice.
    out.verdict = CommandVerdict::kRepeated;
    out.publish = last_;
    return out;
  }
  if (newest_seq_ && seq > *newest_seq_ + 1) out.missing = seq - *newest_seq_ - 1;
  newest_seq_ = seq;
  if (mode_ == Mode::kRealtime) {
    if (held_seq_ >= 0) {
      out.superseded_unapplied = held_applications_ == 0;
      out.extra_applications = std::max<int64_t>(held_applications_ - 1, 0);
    }
    held_command_ = command;
    held_seq_ = seq;
    held_applications_ = 0;
    out.verdict = CommandVerdict::kAccepted;
    return out;
  }
  StepWith(command, seq);
  // The answer to command k is state k + 1 whatever the plant's own count: after a jump ahead
  // (or a first command other than 0) the state keeps naming the command it answers.
  last_.seq = seq + 1;
  out.verdict = out.missing > 0 ? CommandVerdict::kGap : CommandVerdict::kStepped;
  out.publish = last_;
  return out;
}

const PlantSample& PlantSession::Tick() {
  ODONATA_EXPECTS(mode_ == Mode::kRealtime);
  StepWith(held_command_, held_seq_);
  ++held_applications_;
  return last_;
}

}  // namespace odonata::pipeline

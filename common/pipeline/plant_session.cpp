#include "pipeline/plant_session.hpp"

#include <algorithm>
#include <cmath>
#include "contract/precondition.hpp"

#include "sequence/sequence_window.hpp"
#include "vehicle/command_limits.hpp"
#include "vehicle/vehicle_step.hpp"

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
  held_.clear();
  answers_.clear();
  leaps_ = LeapGuard{};
  held_command_ = setup_.trim_command;
  held_seq_ = -1;
  held_applications_ = 0;
  last_ = PlantSample{0, -1, plant_.output(), StatusOf(plant_.output()), plant_.applied_command()};
  return last_;
}

void PlantSession::StepWith(const plant::CommandMatrix& command, int64_t command_seq) {
  const double t_s = static_cast<double>(last_.seq) / plant_.config().integration.sample_rate_hz;
  const vehicle::VehicleStep step = vehicle::StepVehicle(plant_, command, setup_.attitude_hold,
                                                         setup_.hold_gains, setup_.damage, t_s);
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
  // Leaps count from the newest command received: held ones lie up to a window ahead.
  const int64_t newest =
      std::max(newest_seq_.value_or(-1), held_.empty() ? -1 : held_.rbegin()->first);
  out.problem = leaps_.Problem("command", seq, newest);
  if (!out.problem.empty()) return out;  // kRejected
  out.problem = vehicle::CommandLimitProblems(command, plant_.config().limits);
  if (!out.problem.empty()) return out;  // kRejected

  if (mode_ == Mode::kLockstep) {
    const int64_t expected = newest_seq_ ? *newest_seq_ + 1 : 0;
    if (seq < expected) {
      // The generator resent it: a consumer lost our answer (or the generator did). Answer
      // again from the history; do not step twice.
      for (const PlantSample& answer : answers_) {
        if (answer.command_seq != seq) continue;
        out.verdict = CommandVerdict::kRepeated;
        out.publish.push_back(answer);
        return out;
      }
      out.verdict = CommandVerdict::kStale;
      out.problem = "command seq " + std::to_string(seq) + " was applied before the last " +
                    std::to_string(kAnswerHistory) +
                    " answers kept (newest applied: " + std::to_string(expected - 1) + ")";
      return out;
    }
    if (seq > expected) {
      // An earlier command is still on its way (or lost, and the generator will resend it).
      // The first copy of a seq wins, as in the pairing rule (sample_pairer.hpp).
      held_.emplace(seq, command);
      out.verdict = CommandVerdict::kHeld;
      if (held_.size() <= kMaxHeldCommands) return out;
      // A generator that does not resend (a replayed log, a lossy one-way link): go on.
      out.missing = held_.begin()->first - expected;
      out.missing_from = expected;
      ReleaseHeld(&out);
      out.verdict = CommandVerdict::kGap;
      return out;
    }
    StepLockstep(seq, command, &out);
    ReleaseHeld(&out);
    out.verdict = CommandVerdict::kStepped;
    return out;
  }

  if (newest_seq_ && seq <= *newest_seq_) {
    out.verdict = CommandVerdict::kStale;
    out.problem = "command seq " + std::to_string(seq) + " is older than or equal to the newest, " +
                  std::to_string(*newest_seq_);
    return out;
  }
  if (newest_seq_ && seq > *newest_seq_ + 1) {
    out.missing = seq - *newest_seq_ - 1;
    out.missing_from = *newest_seq_ + 1;
  }
  newest_seq_ = seq;
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

static_assert(static_cast<int64_t>(PlantSession::kMaxHeldCommands) > kMaxLockstepWindow,
              "a lockstep window's commands behind a lost one must wait for its resend");

void PlantSession::StepLockstep(int64_t seq, const plant::CommandMatrix& command,
                                CommandOutcome* out) {
  StepWith(command, seq);
  // The answer to command k is state k + 1 whatever the plant's own count: after stepping over
  // a gap the state keeps naming the command it answers.
  last_.seq = seq + 1;
  newest_seq_ = seq;
  answers_.push_back(last_);
  if (answers_.size() > kAnswerHistory) answers_.pop_front();
  out->publish.push_back(last_);
}

void PlantSession::ReleaseHeld(CommandOutcome* out) {
  // After a gap the oldest held command is the next one; after that only consecutive ones.
  if (out->missing > 0 && !held_.empty()) {
    const auto first = held_.begin();
    StepLockstep(first->first, first->second, out);
    held_.erase(first);
  }
  for (auto it = held_.begin(); it != held_.end() && it->first <= *newest_seq_ + 1;) {
    if (it->first == *newest_seq_ + 1) StepLockstep(it->first, it->second, out);
    it = held_.erase(it);  // applied, or a copy of an older one
  }
}

const PlantSample& PlantSession::Tick() {
  ODONATA_EXPECTS(mode_ == Mode::kRealtime);
  StepWith(held_command_, held_seq_);
  ++held_applications_;
  return last_;
}

}  // namespace odonata::pipeline

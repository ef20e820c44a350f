#pragma once
// One learner, two schedules (docs/identifier.md §6.3): the online identifier learns sample by
// sample, and at fixed sample counts refits the model on the samples it keeps — global least
// squares and premise epochs, the offline trainer's own hybrid (NarxModel::Refit). The counts
// are fixed, so a lockstep run and odonata-fit replaying the same rows
// (TrainOptions::refit) refit at the same samples and give the same model bit for bit.

#include <cstdint>
#include <deque>

#include <Eigen/Core>

#include "sysid/narx_model.hpp"

namespace odonata::sysid {

/// Keeps the most recent learned rows and refits the model when the schedule says.
class ReplayRefitter {
 public:
  explicit ReplayRefitter(RefitSchedule schedule) : schedule_(schedule) {}

  /// After sample number `learned` (1-based, counting every sample learned) was learned from
  /// the raw regressor x and targets y: keeps it, and refits `model` on what is kept when due.
  /// @return true when it refitted.
  bool AfterLearn(NarxModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& y,
                  int64_t learned);
  /// Forgets the kept rows (a model from elsewhere replaced this one).
  void Clear() { rows_.clear(); }

  const RefitSchedule& schedule() const { return schedule_; }
  std::size_t kept() const { return rows_.size(); }
  int64_t refits() const { return refits_; }

 private:
  RefitSchedule schedule_;
  std::deque<std::pair<Eigen::VectorXd, Eigen::VectorXd>> rows_;  // oldest first
  int64_t refits_ = 0;
};

}  // namespace odonata::sysid

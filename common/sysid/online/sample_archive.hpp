#pragma once
// The samples a scheduled refit learns from (docs/identifier.md §6.3). Once `buffer` samples have
// been kept it is full, or short by up to three blocks just after a doubling (below): a run of the
// most recent samples, at least RefitSchedule::RecentSamples() long, and before it an archive of
// whole blocks spread over everything older.
// Block b (samples b·L … b·L + L − 1 in the order kept) is archived when b is a multiple of the
// stride; a sample leaving the recent run is archived or dropped by its block, and when the recent
// run would fall below RecentSamples() the stride doubles, dropping every other archived block.
// The archive so stays spread evenly over the whole run, from its first sample, whatever the
// run's length, at a fixed cost; which samples are kept depends on counts only.

#include <cstddef>
#include <cstdint>
#include <deque>
#include <vector>

#include "sysid/model/regressor_spec.hpp"
#include "sysid/model/sample.hpp"
#include "sysid/online/refit_schedule.hpp"

namespace odonata::sysid {

class SampleArchive {
 public:
  /// Keeps nothing when the schedule is off (RefitSchedule::enabled()).
  explicit SampleArchive(const RefitSchedule& schedule) : schedule_(schedule) {}

  void Keep(const Sample& s);
  /// Forgets every sample (a RESET, a restore): the next one kept is the first again.
  void Clear();

  std::size_t size() const { return recent_.size() + archive_.size(); }
  std::size_t recent_size() const { return recent_.size(); }
  /// Archived blocks are the multiples of this (1 until the recent run first reaches its least).
  int64_t stride() const { return stride_; }
  /// Samples kept since the start (or Clear), those dropped since included.
  int64_t kept_since_start() const { return order_ + static_cast<int64_t>(recent_.size()); }
  /// Every sample kept, oldest first (a break at every skipped index): a refit's series.
  Series All() const;
  /// The newest `count` samples of the recent run, oldest first. @pre count <= recent_size().
  Series NewestRecent(std::size_t count) const;

 private:
  struct Archived {
    int64_t order = 0;  // the sample's place among those kept since the start (or Clear)
    Sample sample;
  };
  RefitSchedule schedule_;
  std::deque<Sample> recent_;     ///< oldest first
  std::deque<Archived> archive_;  ///< oldest first, all older than recent_
  int64_t order_ = 0;  ///< samples that have left the recent run: the order of its oldest
  int64_t stride_ = 1;
};

/// The series a refit learns from: the samples in order, a break wherever an index is skipped.
Series SeriesFromSamples(const std::deque<Sample>& samples);

}  // namespace odonata::sysid

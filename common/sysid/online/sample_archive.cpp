#include "sysid/online/sample_archive.hpp"

#include <algorithm>
#include <utility>

namespace odonata::sysid {
namespace {

// The samples in order, each copied once into the series.
Series SeriesFromSampleRefs(const std::vector<const Sample*>& samples) {
  Series s;
  if (samples.empty()) return s;
  const auto n = static_cast<Eigen::Index>(samples.size());
  s.outputs.resize(n, samples.front()->outputs.size());
  s.inputs.resize(n, samples.front()->inputs.size());
  for (Eigen::Index r = 0; r < n; ++r) {
    const Sample& x = *samples[static_cast<std::size_t>(r)];
    s.outputs.row(r) = x.outputs.transpose();
    s.inputs.row(r) = x.inputs.transpose();
    if (r > 0 && x.index != samples[static_cast<std::size_t>(r - 1)]->index + 1)
      s.breaks.push_back(r);
  }
  return s;
}

}  // namespace

Series SeriesFromSamples(const std::deque<Sample>& samples) {
  std::vector<const Sample*> refs;
  refs.reserve(samples.size());
  for (const Sample& x : samples) refs.push_back(&x);
  return SeriesFromSampleRefs(refs);
}

void SampleArchive::Keep(const Sample& s) {
  if (!schedule_.enabled()) return;
  recent_.push_back(s);
  const int64_t block = schedule_.HistoryBlock();
  const auto least = static_cast<std::size_t>(schedule_.RecentSamples());
  while (size() > static_cast<std::size_t>(schedule_.buffer)) {
    if (block > 0 && recent_.size() <= least) {
      stride_ *= 2;
      archive_.erase(
          std::remove_if(archive_.begin(), archive_.end(),
                         [&](const Archived& a) { return (a.order / block) % stride_ != 0; }),
          archive_.end());
      continue;
    }
    // The oldest recent sample leaves the run: archived if its block is one the archive keeps.
    const int64_t order = order_++;
    if (block > 0 && (order / block) % stride_ == 0)
      archive_.push_back(Archived{order, std::move(recent_.front())});
    recent_.pop_front();
  }
}

Series SampleArchive::All() const {
  // Built where a refit starts, on the thread that takes the samples: each copied once.
  std::vector<const Sample*> kept;
  kept.reserve(archive_.size() + recent_.size());
  for (const Archived& a : archive_) kept.push_back(&a.sample);
  for (const Sample& x : recent_) kept.push_back(&x);
  return SeriesFromSampleRefs(kept);
}

Series SampleArchive::NewestRecent(std::size_t count) const {
  std::vector<const Sample*> refs;
  refs.reserve(count);
  for (auto it = recent_.end() - static_cast<std::ptrdiff_t>(count); it != recent_.end(); ++it)
    refs.push_back(&*it);
  return SeriesFromSampleRefs(refs);
}

void SampleArchive::Clear() {
  recent_.clear();
  archive_.clear();
  order_ = 0;
  stride_ = 1;
}

}  // namespace odonata::sysid

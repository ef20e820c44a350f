#include "sysid/online/refit_schedule.hpp"

#include <algorithm>

namespace odonata::sysid {

bool RefitSchedule::Due(int64_t learned) const {
  if (!enabled() || learned < first) return false;
  if (every > 0 && learned >= every) return learned % every == 0;
  // first, 2·first, 4·first, … (below `every`, when there is one)
  int64_t at = first;
  while (at < learned) at *= 2;
  return at == learned;
}

int64_t RefitSchedule::HistoryBlock() const {
  if (!(history > 0.0)) return 0;
  const auto block =
      static_cast<int64_t>(std::min(history, 1.0) * static_cast<double>(buffer)) / kHistoryBlocks;
  return block >= kShortestHistoryBlock ? block : 0;
}

}  // namespace odonata::sysid

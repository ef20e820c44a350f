#include "replay/lockstep_receipts.hpp"

#include <algorithm>

namespace odonata::replay {

LockstepReceipts::LockstepReceipts(std::vector<std::string> consumers) {
  for (const auto& c : consumers) Await(c);
}

void LockstepReceipts::Await(const std::string& instance) {
  if (held_.count(instance)) return;
  consumers_.push_back(instance);
  held_[instance] = -1;
}

void LockstepReceipts::OnReceipt(const std::string& instance, int64_t held, int64_t sent) {
  const auto it = held_.find(instance);
  if (it == held_.end() || held > sent) return;
  // Receipts may arrive out of order; the newest held sample only moves forward within a run.
  it->second = std::max(it->second, held);
}

bool LockstepReceipts::Confirmed(int64_t seq) const {
  return std::all_of(held_.begin(), held_.end(), [seq](const auto& h) { return h.second >= seq; });
}

std::vector<std::string> LockstepReceipts::Missing(int64_t seq) const {
  std::vector<std::string> missing;
  for (const auto& c : consumers_)
    if (held_.at(c) < seq) missing.push_back(c);
  return missing;
}

void LockstepReceipts::Restart() {
  for (auto& h : held_) h.second = -1;
}

}  // namespace odonata::replay

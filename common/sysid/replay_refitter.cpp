#include "sysid/replay_refitter.hpp"

namespace odonata::sysid {

bool RefitSchedule::Due(int64_t learned) const {
  if (!enabled() || learned < first) return false;
  if (every > 0 && learned > every) return learned % every == 0;
  // first, 2·first, 4·first, … (up to `every`, when there is one)
  int64_t at = first;
  while (at < learned) at *= 2;
  return at == learned;
}

bool ReplayRefitter::AfterLearn(NarxModel& model, const Eigen::VectorXd& x,
                                const Eigen::VectorXd& y, int64_t learned) {
  if (!schedule_.enabled()) return false;
  rows_.emplace_back(x, y);
  while (rows_.size() > static_cast<std::size_t>(schedule_.buffer)) rows_.pop_front();
  if (!schedule_.Due(learned)) return false;
  const auto n = static_cast<Eigen::Index>(rows_.size());
  Eigen::MatrixXd xs(n, x.size()), ys(n, y.size());
  for (Eigen::Index r = 0; r < n; ++r) {
    xs.row(r) = rows_[static_cast<std::size_t>(r)].first.transpose();
    ys.row(r) = rows_[static_cast<std::size_t>(r)].second.transpose();
  }
  model.Refit(xs, ys, schedule_.epochs, schedule_.ridge);
  ++refits_;
  return true;
}

}  // namespace odonata::sysid

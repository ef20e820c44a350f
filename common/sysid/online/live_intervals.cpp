#include "sysid/online/live_intervals.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "metrics/conformal.hpp"

namespace odonata::sysid {
namespace {

void Keep(std::vector<std::deque<double>>& kept, const Eigen::VectorXd& measured,
          const Eigen::VectorXd& predicted) {
  kept.resize(static_cast<std::size_t>(measured.size()));
  for (Eigen::Index o = 0; o < measured.size() && o < predicted.size(); ++o) {
    const double e = std::abs(measured(o) - predicted(o));
    if (!std::isfinite(e)) continue;
    auto& q = kept[static_cast<std::size_t>(o)];
    q.push_back(e);
    if (q.size() > LiveIntervals::kWindow) q.pop_front();
  }
}

Eigen::VectorXd Widths(const std::vector<std::deque<double>>& kept, double level) {
  Eigen::VectorXd w(static_cast<Eigen::Index>(kept.size()));
  std::vector<double> e;
  for (std::size_t o = 0; o < kept.size(); ++o) {
    e.assign(kept[o].begin(), kept[o].end());
    w(static_cast<Eigen::Index>(o)) = metrics::ConformalHalfWidth(e, level);
  }
  return w;
}

}  // namespace

LiveIntervals::LiveIntervals(double level) : level_(level) {
  if (!(level > 0.0 && level < 1.0))
    throw std::invalid_argument("the interval's level must be in (0, 1), not " +
                                std::to_string(level));
}

void LiveIntervals::Add(const Eigen::VectorXd& measured, const Eigen::VectorXd& predicted,
                        const Eigen::VectorXd& ahead, const Eigen::VectorXd& free_run) {
  Keep(one_step_, measured, predicted);
  if (ahead.size() > 0) Keep(ahead_, measured, ahead);
  if (free_run.size() > 0) Keep(free_run_, measured, free_run);
  // Until the first recomputation every output's width is unknown (+∞), sized to the outputs.
  if (one_step_width_.size() != measured.size()) Recompute();
  if (++added_ % kRecomputeEvery == 0) Recompute();
}

void LiveIntervals::Recompute() {
  one_step_width_ = Widths(one_step_, level_);
  ahead_width_ = Widths(ahead_, level_);
  free_run_width_ = Widths(free_run_, level_);
}

void LiveIntervals::Seed(const SeedResiduals& seed, int horizon) {
  Clear();
  const auto fill = [](std::vector<std::deque<double>>& kept, const Eigen::MatrixXd& e) {
    kept.assign(static_cast<std::size_t>(e.cols()), {});
    const Eigen::Index first = std::max<Eigen::Index>(0, e.rows() - Eigen::Index{kWindow});
    for (Eigen::Index o = 0; o < e.cols(); ++o)
      for (Eigen::Index r = first; r < e.rows(); ++r)
        if (std::isfinite(e(r, o))) kept[static_cast<std::size_t>(o)].push_back(std::abs(e(r, o)));
  };
  fill(one_step_, seed.one_step);
  if (seed.horizon == horizon && horizon > 1) fill(ahead_, seed.ahead);
  fill(free_run_, seed.free_run);
  Recompute();
}

void LiveIntervals::Clear() {
  one_step_.clear();
  ahead_.clear();
  free_run_.clear();
  one_step_width_.resize(0);
  ahead_width_.resize(0);
  free_run_width_.resize(0);
  added_ = 0;
}

}  // namespace odonata::sysid

// The selection's progress as it is reported (selection_steps.hpp): which candidate leads so far,
// and the choice rule the final choice and the leading one share.

#include <cmath>

#include "sysid/selection/selection_steps.hpp"

namespace odonata::sysid {

Choice SmallestWithinTolerance(const std::vector<Candidate>& cs, const SelectionOptions& options) {
  Choice choice;
  if (cs.empty()) return choice;
  for (std::size_t k = 0; k < cs.size(); ++k)
    if (cs[k].score < cs[choice.best].score) choice.best = k;
  const double allowed = Tolerated(cs[choice.best].score, options);
  choice.chosen = choice.best;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const auto& c = cs[k];
    const auto& now = cs[choice.chosen];
    if (c.score <= allowed &&
        (c.rules < now.rules || (c.rules == now.rules && c.score < now.score)))
      choice.chosen = k;
  }
  return choice;
}

namespace {

// A retrained candidate (the short list's simulation stages, a restart) is the same setting.
bool SameSetting(const Candidate& a, const Candidate& b) {
  const auto from_linear = [](const Candidate& c) {
    return !c.simulation.empty() && c.simulation.front().from_linear;
  };
  return a.linear == b.linear && a.consequent == b.consequent && a.threshold == b.threshold &&
         a.kappa == b.kappa && a.deviation_ridge == b.deviation_ridge &&
         from_linear(a) == from_linear(b);
}

}  // namespace

void SelectionState::Report(const Candidate& c, const Candidate* chosen) {
  if (!on_candidate || total <= 0.0) return;
  const auto same = std::find_if(trained_.begin(), trained_.end(),
                                 [&](const Candidate& t) { return SameSetting(t, c); });
  if (same != trained_.end())
    *same = c;
  else
    trained_.push_back(c);
  SelectionProgress p;
  p.fraction = std::min(1.0, done / total);
  p.fit_rows = fit_rows;
  if (chosen != nullptr) {
    p.leading = *chosen;  // after the checks that may have changed the scores the rule reads
  } else if (options != nullptr) {
    // As the final choice will judge them: a K-step candidate that gave away the one-step bound
    // cannot be chosen.
    std::vector<Candidate> eligible;
    for (const Candidate& t : trained_)
      if (t.linear || !(std::isfinite(result.one_step_bound) &&
                        !(t.holdout_one_step_ndei <= result.one_step_bound)))
        eligible.push_back(t);
    if (!eligible.empty()) p.leading = eligible[SmallestWithinTolerance(eligible, *options).chosen];
  }
  on_candidate(c, p);
}

}  // namespace odonata::sysid

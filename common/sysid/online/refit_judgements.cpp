#include "sysid/online/refit_judgements.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/selection/offline_fit.hpp"

namespace odonata::sysid {

// The selection's linear candidate, if it had one.
std::optional<Candidate> LinearCandidate(const SelectionResult& selection) {
  const auto linear = std::find_if(selection.candidates.begin(), selection.candidates.end(),
                                   [](const Candidate& c) { return c.linear; });
  if (linear == selection.candidates.end()) return std::nullopt;
  return *linear;
}

// The rest deviation a model is held to: the free-run criterion's linear candidate's (NaN: none).
double LinearRest(const SelectionResult& selection) {
  const std::optional<Candidate> linear = LinearCandidate(selection);
  return selection.free_run_criterion && linear ? linear->rest_deviation
                                                : std::numeric_limits<double>::quiet_NaN();
}

// The linear candidate beside a fuzzy choice, to train with each refit; none when the choice is
// the linear model.
std::optional<Candidate> LinearBeside(const SelectionResult& selection) {
  if (selection.candidates[selection.chosen].linear) return std::nullopt;
  return LinearCandidate(selection);
}

bool IncumbentHoldsItsOwn(const NarxModel& incumbent, const SelectionResult& selection,
                          const Series& series, const SelectionOptions& options) {
  // The hold-out is the newest samples, which the incumbent (it began before them) never saw, as
  // the chosen candidate did not (trained on the fit slice): the same test for both. A search
  // on blocks of a longer buffer has no such slice of it.
  if (selection.fit_samples + selection.holdout_samples != series.samples()) return false;
  const Series holdout = SliceSeries(series, selection.fit_samples, selection.holdout_samples);
  const double held = incumbent.NdeiAhead(holdout, selection.criterion_horizon);
  if (!(std::isfinite(held) &&
        BeatsByMargin(held, selection.candidates[selection.chosen].score, options)))
    return false;
  // A fuzzy incumbent must also beat the linear model there, by the same margin: the chosen
  // candidate faced the linear model in cross-validation, the incumbent never did.
  const std::optional<Candidate> linear = LinearCandidate(selection);
  if (incumbent.total_rules() > incumbent.outputs() && linear && std::isfinite(linear->score) &&
      !BeatsByMargin(held, linear->score, options))
    return false;
  // The checks a refit's own model passes: it runs on the whole buffer without diverging and,
  // with the free-run criterion, comes to rest where the linear model does.
  return SteadyStateHolds(incumbent, series, selection.criterion_horizon, LinearRest(selection));
}

NarxModel RefineExpert(const NarxModel& expert, const Series& series) {
  NarxModel refined = expert;
  const RegressionData d = BuildRegression(expert.spec(), series);
  const Eigen::MatrixXd xs = expert.scaling().ScaleRegressorRows(d.x);
  const Eigen::MatrixXd ys = expert.scaling().ScaleOutputRows(d.y);
  // The solve's own ridge (TrainOptions::ridge); a failed solve leaves that output as written.
  for (int o = 0; o < expert.outputs(); ++o)
    refined.mutable_model(o).RefineConsequents(xs, ys.col(o), TrainOptions{}.ridge);
  return refined;
}

bool ExpertHoldsItsOwn(const NarxModel& expert, const SelectionResult& selection,
                       const Series& series, const SelectionOptions& options) {
  if (selection.fit_samples + selection.holdout_samples != series.samples()) return true;
  const NarxModel refined = RefineExpert(expert, SliceSeries(series, 0, selection.fit_samples));
  const double held =
      refined.NdeiAhead(SliceSeries(series, selection.fit_samples, selection.holdout_samples),
                        selection.criterion_horizon);
  const double chosen = selection.candidates[selection.chosen].score;
  return !(std::isfinite(chosen) && BeatsByMargin(chosen, held, options));
}

bool LinearWinsTheNewSamples(const NarxModel& fuzzy, const NarxModel& linear, const Series& fresh,
                             int criterion_horizon) {
  // A few rows decide nothing.
  if (TargetRows(fuzzy.spec(), fresh).size() < 10) return false;
  // On the thread that takes the samples: K steps ahead, every target costs K predictions, so
  // only every (K/10)-th is scored. All 2 000 took 31 ms 50 steps ahead, where a landing takes
  // under 1 ms (bench_refit_realtime --horizon 50); the newest 400 alone judged the tail-sitter's
  // models wrongly both ways.
  const int stride = std::max(1, criterion_horizon / kLandingCheckStrideDivisor);
  const double l = linear.NdeiAhead(fresh, criterion_horizon, stride);
  // A linear model no better than the samples' own mean says only that neither model knows
  // them (the plant moved somewhere new); the fuzzy one, tracked, may still learn it fastest.
  if (!(l < 1.0)) return false;
  // NdeiAhead is +∞ for a model that runs away, which any finite score beats.
  return BeatsByMargin(l, fuzzy.NdeiAhead(fresh, criterion_horizon, stride), SelectionOptions{});
}

bool SteadyStateHolds(const NarxModel& model, const Series& series, int criterion_horizon,
                      double linear_rest) {
  if (!std::isfinite(model.NdeiAhead(series, criterion_horizon))) return false;
  return !(std::isfinite(linear_rest) && Restless(RestDeviation(model, series), linear_rest));
}

}  // namespace odonata::sysid

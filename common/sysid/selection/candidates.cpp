// The candidate settings a selection tries (entropy thresholds, κ, the consequent), the series
// cut and joined for hold-outs and folds, and one candidate's training and score.

#include <algorithm>
#include <cmath>
#include <limits>

#include "sysid/estimation/narx_training.hpp"
#include "sysid/selection/model_selection.hpp"
#include "sysid/selection/selection_steps.hpp"

namespace odonata::sysid {

double ThresholdForRadius(double radius) {
  return fuzzy::EntropyRuleGenerator::FiringEntropy(std::exp(-0.5 * radius * radius));
}

std::vector<double> DefaultThresholds() {
  std::vector<double> t;
  for (double r : {2.0, 1.6, 1.3, 1.1, 0.9, 0.75, 0.6, 0.5}) t.push_back(ThresholdForRadius(r));
  return t;
}

std::vector<double> DefaultKappas() { return {0.5, 1.0, 2.0}; }

Series SliceSeries(const Series& s, Eigen::Index begin, Eigen::Index count) {
  Series out;
  out.outputs = s.outputs.middleRows(begin, count);
  out.inputs = s.inputs.middleRows(begin, count);
  for (const Eigen::Index b : s.breaks)
    if (b > begin && b < begin + count) out.breaks.push_back(b - begin);
  return out;
}

HoldoutSplit SplitAtHoldout(const Series& train, Eigen::Index holdout_samples) {
  const Eigen::Index rows = train.samples();
  const Eigen::Index held = std::clamp<Eigen::Index>(holdout_samples, 0, rows);
  return {SliceSeries(train, 0, rows - held), SliceSeries(train, rows - held, held)};
}

Series ConcatSeries(const Series& a, const Series& b) {
  Series out;
  out.outputs.resize(a.samples() + b.samples(), a.outputs.cols());
  out.inputs.resize(a.samples() + b.samples(), a.inputs.cols());
  out.outputs << a.outputs, b.outputs;
  out.inputs << a.inputs, b.inputs;
  out.breaks = a.breaks;
  if (a.samples() > 0 && b.samples() > 0) out.breaks.push_back(a.samples());
  for (const Eigen::Index k : b.breaks) out.breaks.push_back(a.samples() + k);
  return out;
}

fuzzy::FuzzyModelConfig CandidateConfig(const fuzzy::FuzzyModelConfig& base, const Candidate& c) {
  fuzzy::FuzzyModelConfig cfg = base;
  cfg.consequent = c.consequent;
  cfg.entropy.threshold = c.threshold;
  cfg.entropy.kappa = c.kappa;
  if (c.linear) cfg.entropy.max_rules = 1;
  return cfg;
}

// The largest score within the candidates' tolerance of `score`: 5 % or 0.005 NDEI above it.
double Tolerated(double score, const SelectionOptions& options) {
  return std::max(score * (1.0 + options.relative_tolerance), score + options.absolute_tolerance);
}

NarxModel TrainCandidate(const SelectionContext& ctx, const Candidate& c, const Series& fit,
                         const Series* holdout, int epochs, TrainReport* report,
                         bool with_simulation) {
  NarxModel model(ctx.spec, CandidateConfig(ctx.base, c));
  TrainOptions t = ctx.train_options;
  if (ctx.options.scaling) {
    model.SetScaling(*ctx.options.scaling);
    t.fit_scaling = false;
  }
  t.progress = {};
  t.simulation_progress = {};
  t.deviation_ridge = c.deviation_ridge;
  t.epochs = epochs;
  t.holdout = holdout;
  t.holdout_free_run = ctx.horizon == 0;
  t.holdout_horizon = ctx.horizon > 1 ? ctx.horizon : 0;
  t.patience = holdout != nullptr ? ctx.options.patience : 0;
  t.simulation.clear();
  if (with_simulation) t.simulation = c.simulation;
  const TrainReport r = Train(model, fit, t);
  if (report) *report = r;
  return model;
}

void ScoreCandidate(const SelectionContext& ctx, Candidate& c, const NarxModel& model) {
  c.rules = model.total_rules();
  c.holdout_one_step_ndei = model.Ndei(ctx.holdout, false);
  c.holdout_free_run_ndei = ctx.spec.output_lags > 0 ? model.Ndei(ctx.holdout, true)
                                                     : std::numeric_limits<double>::quiet_NaN();
  c.holdout_ahead_ndei = ctx.horizon > 1 ? model.NdeiAhead(ctx.holdout, ctx.horizon)
                                         : std::numeric_limits<double>::quiet_NaN();
  c.score = ctx.horizon == 0   ? c.holdout_free_run_ndei
            : ctx.horizon == 1 ? c.holdout_one_step_ndei
                               : c.holdout_ahead_ndei;
  if (!std::isfinite(c.score)) c.score = std::numeric_limits<double>::infinity();
}

// The criterion's NDEI: free run (horizon 0), one step (1) or `horizon` steps ahead.
double Score(const NarxModel& model, const Series& s, int horizon) {
  const double v = model.NdeiAhead(s, horizon);
  return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
}

}  // namespace odonata::sysid

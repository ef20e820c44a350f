#include "sysid/model_selection.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "fuzzy/entropy_rule_generator.hpp"

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

SelectionResult SelectModel(
    const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
    const TrainOptions& train_options, const Series& train, const SelectionOptions& options,
    const std::function<void(const Candidate&, std::size_t, std::size_t)>& on_candidate,
    const Series* selection) {
  const auto kinds = options.consequents.empty()
                         ? std::vector<fuzzy::ConsequentKind>{fuzzy::ConsequentKind::kLinear,
                                                              fuzzy::ConsequentKind::kSingleton}
                         : options.consequents;
  auto thresholds = options.thresholds.empty() ? DefaultThresholds() : options.thresholds;
  std::sort(thresholds.begin(), thresholds.end());
  const auto kappas = options.kappas.empty() ? DefaultKappas() : options.kappas;
  if (!(options.holdout_fraction > 0.0 && options.holdout_fraction < 1.0))
    throw std::invalid_argument("hold-out fraction must be in (0, 1)");
  SelectionResult result;
  const int need = spec.first_target() + 2;
  if (selection != nullptr) {
    result.fit_samples = train.samples();
    result.holdout_samples = selection->samples();
  } else {
    result.holdout_samples =
        static_cast<Eigen::Index>(std::llround(options.holdout_fraction * double(train.samples())));
    result.fit_samples = train.samples() - result.holdout_samples;
  }
  if (result.holdout_samples < need || result.fit_samples < need)
    throw std::invalid_argument("the training data (" + std::to_string(train.samples()) +
                                " samples) is too short to hold out " +
                                std::to_string(result.holdout_samples) + " for model selection");
  const Series fit = selection != nullptr ? train : SliceSeries(train, 0, result.fit_samples);
  const Series holdout = selection != nullptr
                             ? *selection
                             : SliceSeries(train, result.fit_samples, result.holdout_samples);
  result.free_run_criterion =
      spec.output_lags > 0 && options.criterion != SelectionCriterion::kOneStep;

  const std::size_t total = kinds.size() * thresholds.size() * kappas.size();
  std::size_t done = 0;
  for (const auto kind : kinds) {
    for (const double kappa : kappas) {
      bool capped = false;
      for (const double h : thresholds) {
        ++done;
        if (capped) continue;
        fuzzy::FuzzyModelConfig cfg = base;
        cfg.consequent = kind;
        cfg.entropy.threshold = h;
        cfg.entropy.kappa = kappa;
        NarxModel model(spec, cfg);
        TrainOptions t = train_options;
        if (options.scaling) {
          model.SetScaling(*options.scaling);
          t.fit_scaling = false;
        }
        t.progress = {};
        t.epochs = options.max_epochs;
        t.holdout = &holdout;
        t.holdout_free_run = result.free_run_criterion;
        t.patience = options.patience;
        const TrainReport report = model.Train(fit, t);
        Candidate c;
        c.consequent = kind;
        c.threshold = h;
        c.kappa = kappa;
        c.epochs = report.kept_epoch;
        c.rules = model.total_rules();
        c.at_cap = c.rules >= cfg.entropy.max_rules * model.outputs();
        capped = c.at_cap;
        c.holdout_one_step_ndei = model.Ndei(holdout, false);
        c.holdout_free_run_ndei = spec.output_lags > 0 ? model.Ndei(holdout, true)
                                                       : std::numeric_limits<double>::quiet_NaN();
        c.score = result.free_run_criterion ? c.holdout_free_run_ndei : c.holdout_one_step_ndei;
        if (!std::isfinite(c.score)) c.score = std::numeric_limits<double>::infinity();
        result.candidates.push_back(c);
        if (on_candidate) on_candidate(c, done, total);
      }
    }
  }
  auto& cs = result.candidates;
  for (std::size_t k = 0; k < cs.size(); ++k)
    if (cs[k].score < cs[result.best].score) result.best = k;
  const double allowed = std::max(cs[result.best].score * (1.0 + options.relative_tolerance),
                                  cs[result.best].score + options.absolute_tolerance);
  result.chosen = result.best;
  for (std::size_t k = 0; k < cs.size(); ++k) {
    const auto& c = cs[k];
    const auto& now = cs[result.chosen];
    if (c.score <= allowed &&
        (c.rules < now.rules || (c.rules == now.rules && c.score < now.score)))
      result.chosen = k;
  }

  const Candidate& c = cs[result.chosen];
  std::ostringstream w;
  auto at_edge = [](const std::vector<double>& grid, double v) {
    if (grid.size() < 2) return false;
    const auto [lo, hi] = std::minmax_element(grid.begin(), grid.end());
    return v == *lo || v == *hi;
  };
  if (!std::isfinite(cs[result.best].score))
    result.warnings.push_back("every candidate diverged on the hold-out slice");
  if (at_edge(thresholds, c.threshold)) {
    w << "the H̄ search stopped at the edge of its grid (H̄ = " << c.threshold
      << "): a wider range may do better";
    result.warnings.push_back(w.str());
    w.str("");
  }
  if (at_edge(kappas, c.kappa)) {
    w << "the κ search stopped at the edge of its grid (κ = " << c.kappa << ")";
    result.warnings.push_back(w.str());
    w.str("");
  }
  if (c.at_cap) {
    w << "the chosen model reached the rule cap (" << c.rules << " rules): raise --max-rules";
    result.warnings.push_back(w.str());
    w.str("");
  }
  if (c.epochs >= options.max_epochs && options.max_epochs > 1) {
    w << "the chosen model still improved at its last epoch (" << c.epochs << ")";
    result.warnings.push_back(w.str());
  }
  return result;
}

}  // namespace odonata::sysid

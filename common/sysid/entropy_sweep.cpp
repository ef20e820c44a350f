#include "sysid/entropy_sweep.hpp"

#include <cmath>
#include <limits>

#include "metrics/accuracy.hpp"
#include "sysid/free_run.hpp"

namespace odonata::sysid {

std::vector<double> DefaultThresholds() {
  std::vector<double> t;
  const int n = 12;
  for (int i = 0; i < n; ++i) t.push_back(1e-3 * std::pow(450.0, i / double(n - 1)));
  return t;
}

SweepResult SweepEntropyThreshold(
    const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
    const TrainOptions& train_options, const Series& train, const Series& validate,
    const SweepOptions& options,
    const std::function<void(const SweepPoint&, std::size_t, std::size_t)>& on_point) {
  const auto thresholds = options.thresholds.empty() ? DefaultThresholds() : options.thresholds;
  const RegressionData vd = BuildRegression(spec, validate);
  SweepResult result;
  for (std::size_t k = 0; k < thresholds.size(); ++k) {
    fuzzy::FuzzyModelConfig cfg = base;
    cfg.entropy.threshold = thresholds[k];
    NarxModel model(spec, cfg);
    TrainOptions quiet = train_options;
    quiet.progress = {};
    model.Train(train, quiet);
    const Predictor predict = [&model](const Eigen::VectorXd& x) { return model.Predict(x); };
    SweepPoint p;
    p.threshold = thresholds[k];
    p.rules = model.total_rules();
    const Eigen::MatrixXd one = PredictOneStep(spec, validate, predict);
    p.validation_one_step_fit_percent = metrics::Score(vd.y.col(0), one.col(0)).fit_percent;
    p.validation_free_run_fit_percent = std::numeric_limits<double>::quiet_NaN();
    if (spec.output_lags > 0) {
      const Eigen::MatrixXd sim = SimulateFreeRun(spec, validate, predict);
      p.validation_free_run_fit_percent = metrics::Score(vd.y.col(0), sim.col(0)).fit_percent;
    }
    p.validation_fit_percent = options.free_run_criterion && spec.output_lags > 0
                                   ? p.validation_free_run_fit_percent
                                   : p.validation_one_step_fit_percent;
    if (!std::isfinite(p.validation_fit_percent)) p.validation_fit_percent = -1e300;
    result.points.push_back(p);
    if (on_point) on_point(p, k + 1, thresholds.size());
  }
  for (std::size_t k = 0; k < result.points.size(); ++k) {
    if (result.points[k].validation_fit_percent > result.points[result.best].validation_fit_percent)
      result.best = k;
  }
  const double floor =
      result.points[result.best].validation_fit_percent - options.tolerance_percent;
  result.chosen = result.best;
  for (std::size_t k = 0; k < result.points.size(); ++k) {
    const auto& p = result.points[k];
    const auto& c = result.points[result.chosen];
    if (p.validation_fit_percent >= floor &&
        (p.rules < c.rules ||
         (p.rules == c.rules && p.validation_fit_percent > c.validation_fit_percent)))
      result.chosen = k;
  }
  return result;
}

}  // namespace odonata::sysid

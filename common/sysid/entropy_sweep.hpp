#pragma once
// "Adjust H̄ until the objective is met", automated: accuracy against rule count over H̄.

#include <functional>
#include <vector>

#include "sysid/narx_model.hpp"

namespace odonata::sysid {

struct SweepPoint {
  double threshold = 0.0;
  int rules = 0;
  double validation_fit_percent = 0.0;  ///< by the sweep's criterion (one-step or free-run)
  double validation_one_step_fit_percent = 0.0;
  double validation_free_run_fit_percent = 0.0;  ///< NaN when there are no output lags
};

struct SweepOptions {
  std::vector<double> thresholds;   ///< H̄ values to try; empty ⇒ DefaultThresholds()
  bool free_run_criterion = false;  ///< score by free-run FIT instead of one-step FIT
  double tolerance_percent = 1.0;   ///< pick the fewest rules within this of the best FIT
};

struct SweepResult {
  std::vector<SweepPoint> points;
  std::size_t best = 0;    ///< index of the most accurate point
  std::size_t chosen = 0;  ///< index of the smallest model within tolerance of the best
};

/// Log-spaced H̄ from 1e-3 to 0.45 (the paper's range plus margin), 12 points.
std::vector<double> DefaultThresholds();

/// Trains one model per threshold on `train` and scores it on `validate`.
/// `on_point` (optional) is called after each point, for progress.
SweepResult SweepEntropyThreshold(
    const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
    const TrainOptions& train_options, const Series& train, const Series& validate,
    const SweepOptions& options,
    const std::function<void(const SweepPoint&, std::size_t, std::size_t)>& on_point = {});

}  // namespace odonata::sysid

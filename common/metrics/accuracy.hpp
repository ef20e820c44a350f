#pragma once
// Accuracy measures of a model output against the measured output (docs/identifier.md §8).

#include <limits>

#include <Eigen/Core>

namespace odonata::metrics {

/// Accuracy of ŷ against y over one window. FIT is what the paper calls "accuracy".
struct Accuracy {
  double fit_percent = 0.0;  ///< 100 (1 − ‖y − ŷ‖₂ / ‖y − ȳ‖₂), MATLAB compare's NRMSE fit.
  double vaf_percent = 0.0;  ///< 100 (1 − var(y − ŷ) / var(y)).
  double rmse = 0.0;         ///< sqrt(mean((y − ŷ)²)), in the output's unit.
  double ndei = 0.0;         ///< RMSE / std(y) = 1 − FIT/100.
  long samples = 0;
};

/// A FIT below this (an error over twice the output's spread) is a prediction that ran
/// away: every tool prints it as "diverges", never as a number of 28 digits.
inline constexpr double kDivergedFitPercent = -100.0;

/// Whether a FIT means "diverges": finite and below kDivergedFitPercent (an infinite one comes
/// from a measured signal that never moves, which is no divergence).
inline bool FitDiverges(double fit_percent) {
  return fit_percent < kDivergedFitPercent &&
         fit_percent > -std::numeric_limits<double>::infinity();
}

/// FIT % from the error's norm ‖y − ŷ‖ and the measured signal's spread ‖y − ȳ‖: a constant
/// signal (spread 0) gives −inf unless the error is 0 (then 100).
double FitPercent(double error_norm, double spread);

/// Scores `predicted` against `measured`.
/// @pre equal sizes, at least one sample. A constant measured signal gives FIT = VAF = −inf
/// unless the prediction is exact (then 100), which is the honest answer.
Accuracy Score(const Eigen::Ref<const Eigen::VectorXd>& measured,
               const Eigen::Ref<const Eigen::VectorXd>& predicted);

}  // namespace odonata::metrics

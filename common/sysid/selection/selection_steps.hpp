#pragma once
// The steps SelectModel is made of, shared by its files (candidates.cpp, linear_check.cpp,
// model_selection.cpp): internal to selection/, not an interface.

#include <vector>

#include "sysid/selection/model_selection.hpp"

namespace odonata::sysid {

/// Levenberg–Marquardt iterations at most for a model's output-error fit (the linear model
/// converges in far fewer).
inline constexpr int kOutputErrorIterations = 50;

/// The largest score within the candidates' tolerance of `score`: 5 % or 0.005 NDEI above it.
double Tolerated(double score, const SelectionOptions& options);

/// Trains `c`'s setting on `fit` (epochs as given, the hold-out choosing among them when there
/// is one) and returns the model.
NarxModel TrainCandidate(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
                         const TrainOptions& train_options, const SelectionOptions& options,
                         const Candidate& c, const Series& fit, const Series* holdout, int horizon,
                         int epochs, TrainReport* report = nullptr, bool with_simulation = false);

/// The criterion's NDEI: free run (horizon 0), one step (1) or `horizon` steps ahead.
double Score(const NarxModel& model, const Series& s, int horizon);

/// Blocked cross-validation of the chosen fuzzy setting against the linear model: fold k is
/// scored after training on the rest of `train`, the seam a break. `linear_folds`, when given,
/// are the linear model's fold scores from an earlier check. `second_look`: the fuzzy candidate
/// is not the hold-out's choice, so the folds alone must show that it beats the linear model.
LinearCheck CrossValidate(const RegressorSpec& spec, const fuzzy::FuzzyModelConfig& base,
                          const TrainOptions& train_options, const SelectionOptions& options,
                          const Candidate& fuzzy_c, const Candidate& linear_c, const Series& train,
                          int horizon, const std::vector<double>* linear_folds = nullptr,
                          bool second_look = false);

}  // namespace odonata::sysid

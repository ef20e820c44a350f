#pragma once
// Training for what is reported: the free-run (simulation) error, by multiple shooting
// (docs/identifier.md §12). The targets are cut into windows of H samples; each window's
// simulation starts from measured outputs and runs on its own predictions, and the loss is the
// squared simulation error over every window. Its gradient runs back through the recursion
// (backpropagation through time) for every parameter, premises and consequents alike, through the
// same kernel the one-step learner uses; iRprop− steps on it, a step that raises the loss is
// undone. One-step least squares stays the starting point.

#include <limits>
#include <vector>

#include <Eigen/Core>

#include "sysid/estimation/train_options.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {

/// ∂L/∂θ per output, laid out like the model's parameters.
struct SimulationGradient {
  std::vector<Eigen::ArrayXXd> centres;      ///< rules × inputs, per output
  std::vector<Eigen::ArrayXXd> sigmas;       ///< rules × inputs, per output
  std::vector<Eigen::VectorXd> consequents;  ///< Consequent::Parameters() layout, per output
};

/// The multiple-shooting loss in scaled units, Σ over windows, targets and outputs of
/// (ŷ − y)²; +∞ when a simulation leaves the finite numbers. With `gradient`, also ∂L/∂θ.
/// @param horizon window length H ≥ 1 (a segment's last window may be shorter).
double SimulationLoss(const NarxModel& model, const Series& series, int horizon,
                      SimulationGradient* gradient = nullptr);

/// The same loss (no gradient) and, in `jtj` and `jte`, the Gauss–Newton normal equations JᵀJ
/// and Jᵀe of every output's parameters, stacked in output order (J = ∂ŷ/∂θ along the windows,
/// by forward sensitivities through the recursion; zero where an output is held at a limit).
/// +∞ when a simulation leaves the finite numbers. An output's parameters are its consequents
/// and, with `premises`, then its centres and its widths (rules × inputs, column by column),
/// through the same premise kernel. With `tie` (consequents alone): in the parameters g the
/// consequents are tied to, θ = `tie` g, i.e. J T for J.
double NormalEquations(const NarxModel& model, const Series& series, int horizon, bool premises,
                       Eigen::MatrixXd& jtj, Eigen::VectorXd& jte,
                       const Eigen::MatrixXd* tie = nullptr);

/// The default schedule: windows growing fourfold from 10 to 640 samples, 30 steps each. Short
/// windows first: a model trained one step ahead may not survive a long simulation yet, and a
/// short window's loss is smooth; longer ones then teach the slow modes.
std::vector<SimulationStage> DefaultSimulationStages();

struct SimulationTrainOptions {
  std::vector<SimulationStage> stages = DefaultSimulationStages();
  /// Optional hold-out: the parameters with the lowest free-run NDEI on it, over every step of
  /// every stage, are kept, and a stage ends after `patience` steps without improving it (0:
  /// never). Without one, every stage takes exactly its steps.
  const Series* holdout = nullptr;
  int holdout_horizon = 0;  ///< the hold-out's score: free run (0) or this many steps ahead
  /// With a hold-out: a step is kept only while its one-step hold-out NDEI is at most this
  /// (TrainOptions::holdout_one_step_bound).
  double one_step_bound = std::numeric_limits<double>::infinity();
  int patience = 8;
  ProgressCallback progress;  ///< (stage, step, steps) after each step
};

struct SimulationTrainReport {
  double initial_loss = 0.0;  ///< at the first stage's horizon
  /// The schedule that reproduces the kept parameters without a hold-out: each stage's steps up
  /// to the kept one (empty: the starting parameters were kept).
  std::vector<SimulationStage> kept;
  std::vector<double> holdout_ndei;  ///< per step, when there is a hold-out
};

/// Trains `model` (already initialised, e.g. by NarxModel::Train) on the simulation error over
/// `train`. Needs output lags; the rule structure stays as it is.
/// @throws std::invalid_argument without output lags or with horizon < 1.
SimulationTrainReport TrainOnSimulationError(NarxModel& model, const Series& train,
                                             const SimulationTrainOptions& options);

}  // namespace odonata::sysid

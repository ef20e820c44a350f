// The offline estimation of a NARX model (narx_training.hpp). Here, with the estimators, so that
// the model (sysid/model/) knows nothing of how it is estimated and no include runs back.

#include <algorithm>
#include <cmath>
#include <functional>

#include "metrics/accuracy.hpp"
#include "sysid/estimation/narx_training.hpp"
#include "sysid/estimation/rprop.hpp"
#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/model/free_run.hpp"
#include "sysid/model/narx_model.hpp"

namespace odonata::sysid {
namespace {

/// iRprop− for one output's centres and widths.
struct RpropState {
  static constexpr double kInitialStep = 0.01;  // scaled units
  Rprop centres, sigmas;

  void Reset(int rules, int inputs) {
    centres.Reset(rules, inputs, kInitialStep);
    sigmas.Reset(rules, inputs, kInitialStep);
  }
  void Backtrack() {
    centres.Backtrack();
    sigmas.Backtrack();
  }
};

// One batch-gradient step of one output's premises (iRprop−), the gradient taken at the firings
// a least-squares pass kept when they are these premises' (`phi` rows × rules), else evaluated.
void StepPremises(fuzzy::FuzzyModel& m, const Eigen::MatrixXd& xs,
                  const Eigen::Ref<const Eigen::VectorXd>& y, const Eigen::ArrayXXd* phi,
                  RpropState& st, const std::function<void(long)>& progress) {
  const int r = m.rules();
  const int inputs = m.inputs();
  if (!st.centres.Matches(r, inputs)) st.Reset(r, inputs);
  Eigen::ArrayXXd gc = Eigen::ArrayXXd::Zero(r, inputs);
  Eigen::ArrayXXd gs = Eigen::ArrayXXd::Zero(r, inputs);
  const bool known = phi != nullptr && phi->rows() == xs.rows() && phi->cols() == r;
  for (Eigen::Index k = 0; k < xs.rows(); ++k) {
    if (known)
      m.AccumulatePremiseGradientAt(xs.row(k).transpose(), phi->row(k).transpose(), y(k), &gc, &gs);
    else
      m.AccumulatePremiseGradient(xs.row(k).transpose(), y(k), &gc, &gs);
    progress(k + 1);
  }
  m.StepPremises(st.centres.Step(gc), st.sigmas.Step(gs));
}

// Firings kept between epochs, at most (rows × rules over the outputs): 16 MB, enough for a
// search's largest candidates (20 000 rows, 100 rules); a long record's final fit evaluates them
// again rather than hold 80 MB (360 000 rows, 28 rules) and raise the fit's peak memory.
constexpr Eigen::Index kKeptFirings = Eigen::Index{2} << 20;

// What an epoch is judged by: the training loss (scaled units, summed over outputs) and the
// one-step FIT (mean over outputs). From the least-squares solves' residuals when every solve gave
// them; else by predicting every row.
class TrainingLoss {
 public:
  TrainingLoss(const Eigen::MatrixXd& xs, const Eigen::MatrixXd& ys)
      : xs_(xs), ys_(ys), spreads_(ys.cols()) {
    for (Eigen::Index o = 0; o < ys.cols(); ++o)
      spreads_(o) = (ys.col(o).array() - ys.col(o).mean()).matrix().norm();
  }

  double FromResiduals(const Eigen::VectorXd& squares, double* fit) const {
    double fit_sum = 0.0;
    for (Eigen::Index o = 0; o < squares.size(); ++o)
      fit_sum += metrics::FitPercent(std::sqrt(squares(o)), spreads_(o));
    *fit = fit_sum / static_cast<double>(squares.size());
    return Finite(squares.sum());
  }

  double ByPrediction(const std::vector<fuzzy::FuzzyModel>& models, double* fit) const {
    double loss = 0.0, fit_sum = 0.0;
    Eigen::VectorXd yhat(xs_.rows());
    for (std::size_t o = 0; o < models.size(); ++o) {
      for (Eigen::Index r = 0; r < xs_.rows(); ++r)
        yhat(r) = models[o].Predict(xs_.row(r).transpose());
      const auto col = ys_.col(static_cast<Eigen::Index>(o));
      loss += (yhat - col).squaredNorm();
      fit_sum += metrics::Score(col, yhat).fit_percent;
    }
    *fit = fit_sum / static_cast<double>(models.size());
    return Finite(loss);
  }

 private:
  const Eigen::MatrixXd& xs_;
  const Eigen::MatrixXd& ys_;
  Eigen::VectorXd spreads_;
  static double Finite(double v) {
    return std::isfinite(v) ? v : std::numeric_limits<double>::infinity();
  }
};
}  // namespace

TrainReport Train(NarxModel& model, const Series& train, const TrainOptions& options) {
  return NarxTrainer::Train(model, train, options);
}

TrainReport NarxTrainer::Train(NarxModel& model, const Series& train, const TrainOptions& options) {
  const RegressionData d = BuildRegression(model.spec_, train);
  if (options.fit_scaling) model.scaling_ = Scaling::FromData(d.x, d.y);
  if (options.detect_output_limits) model.limits_ = OutputLimits::Detect(train.outputs);
  // The envelope is the trained model's: while it trains, every prediction is the rules' own.
  model.envelope_ = DataEnvelope{};
  const Eigen::Index rows = d.x.rows();
  const Eigen::MatrixXd xs = model.scaling_.ScaleRegressorRows(d.x);
  const Eigen::MatrixXd ys = model.scaling_.ScaleOutputRows(d.y);
  const TrainingLoss training_loss(xs, ys);
  // The least squares' firings at the premises it solved for: when the epoch is kept, the next
  // epoch's premise gradient is taken at the same premises and need not evaluate them again.
  std::vector<Eigen::ArrayXXd> firings(static_cast<std::size_t>(model.outputs()));
  bool firings_known = false;
  TrainReport report;
  double rate_scale = 1.0;
  double best_loss = std::numeric_limits<double>::infinity();
  double best_fit = 0.0;  // training FIT of the parameters behind best_loss
  double best_holdout = std::numeric_limits<double>::infinity();
  int best_holdout_epoch = 0;
  std::vector<fuzzy::FuzzyModel> kept_holdout;  // the parameters of the best hold-out epoch
  int since_improvement = 0;
  std::vector<RpropState> rprop(static_cast<std::size_t>(model.outputs()));
  for (int epoch = 0; epoch < options.epochs; ++epoch) {
    if (options.cancel && options.cancel->load()) throw TrainingCancelled();
    fuzzy::LearnMode mode =
        epoch == 0 && options.grow_rules ? fuzzy::LearnMode::kGrowAndTune : fuzzy::LearnMode::kTune;
    // Once least squares owns the consequents, later passes only move the antecedents: an online
    // consequent update would only pull them away from the optimum just solved.
    if (epoch > 0 && options.refine_least_squares) mode = fuzzy::LearnMode::kTunePremises;
    std::vector<fuzzy::FuzzyModel> before;
    if (epoch > 0) before = model.models_;
    if (epoch > 0 && options.refine_least_squares) {
      // The hybrid rule's premise half, offline: one batch-gradient step per pass with a
      // per-parameter step size (iRprop−, Igel & Hüsken 2000), then the least-squares solve.
      for (int o = 0; o < model.outputs(); ++o) {
        const auto& phi = firings[static_cast<std::size_t>(o)];
        StepPremises(model.models_[static_cast<std::size_t>(o)], xs, ys.col(o),
                     firings_known ? &phi : nullptr, rprop[static_cast<std::size_t>(o)],
                     [&](long k) {
                       if (options.progress && ((k - 1) % 1024 == 0 || k == rows))
                         options.progress(epoch, k, rows);
                     });
      }
    } else {
      for (Eigen::Index r = 0; r < rows; ++r) {
        const Eigen::VectorXd x = xs.row(r).transpose();
        for (int o = 0; o < model.outputs(); ++o)
          model.models_[static_cast<std::size_t>(o)].Learn(x, ys(r, o), mode, rate_scale);
        if (options.progress && (r % 1024 == 0 || r + 1 == rows))
          options.progress(epoch, r + 1, rows);
      }
    }
    // The solve's own residuals give the training loss; without it (or if a solve failed) a pass.
    bool loss_solved = false;
    Eigen::VectorXd residual_squares(model.outputs());
    if (options.refine_least_squares) {
      // A rule grown on a few samples (an outlier, a transient) cannot be estimated from them;
      // on a short noisy record it fits their noise. It goes before the solve.
      if (mode == fuzzy::LearnMode::kGrowAndTune) {
        report.rules_grown = model.total_rules();
        for (auto& m : model.models_) m.PruneUnsupported(xs, options.min_rule_support);
      }
      loss_solved = true;
      for (int o = 0; o < model.outputs(); ++o) {
        auto& m = model.models_[static_cast<std::size_t>(o)];
        const bool keep = rows * m.rules() <= kKeptFirings / model.outputs();
        loss_solved &= m.RefineConsequents(xs, ys.col(o), options.ridge, options.deviation_ridge,
                                           &residual_squares(o),
                                           keep ? &firings[static_cast<std::size_t>(o)] : nullptr);
        if (!keep) firings[static_cast<std::size_t>(o)].resize(0, 0);
      }
    }
    firings_known = loss_solved;
    EpochRecord rec;
    rec.epoch = epoch + 1;
    rec.rate_scale = rate_scale;
    const double loss = loss_solved ? training_loss.FromResiduals(residual_squares, &rec.train_fit)
                                    : training_loss.ByPrediction(model.models_, &rec.train_fit);
    if (epoch > 0 && !(loss <= best_loss)) {
      // Backtracking: undo the pass and retry with half the premise step.
      model.models_ = std::move(before);
      firings_known = false;  // they were the rejected premises'
      rec.accepted = false;
      rate_scale *= 0.5;
      for (auto& st : rprop) st.Backtrack();
      rec.train_fit = best_fit;  // the restored parameters are the last accepted ones
    } else {
      best_loss = loss;
      best_fit = rec.train_fit;
      if (epoch > 0) rate_scale *= 1.1;
    }
    rec.rules = model.total_rules();
    if (rec.accepted) report.kept_epoch = rec.epoch;
    if (options.holdout != nullptr) {
      rec.holdout_ndei = options.holdout_horizon > 0
                             ? model.NdeiAhead(*options.holdout, options.holdout_horizon)
                             : model.Ndei(*options.holdout, options.holdout_free_run);
      if (rec.accepted && rec.holdout_ndei < best_holdout &&
          (std::isinf(options.holdout_one_step_bound) ||
           model.Ndei(*options.holdout, false) <= options.holdout_one_step_bound)) {
        best_holdout = rec.holdout_ndei;
        best_holdout_epoch = rec.epoch;
        kept_holdout = model.models_;
        since_improvement = 0;
      } else {
        ++since_improvement;
      }
    }
    report.epochs.push_back(rec);
    if (options.holdout != nullptr && options.patience > 0 && since_improvement >= options.patience)
      break;
  }
  if (options.holdout != nullptr && !kept_holdout.empty()) {
    model.models_ = std::move(kept_holdout);
    report.kept_epoch = best_holdout_epoch;
  }
  if (!options.simulation.empty() && model.spec_.output_lags > 0) {
    SimulationTrainOptions so;
    so.stages = options.simulation;
    std::vector<long> steps_before(so.stages.size() + 1, 0);  // of the stages before each
    for (std::size_t k = 0; k < so.stages.size(); ++k)
      steps_before[k + 1] = steps_before[k] + so.stages[k].steps;
    if (options.cancel || options.simulation_progress)
      so.progress = [cancel = options.cancel, progress = options.simulation_progress, steps_before](
                        int stage, long step, long) {
        if (cancel && cancel->load()) throw TrainingCancelled();
        if (progress)
          progress(stage, steps_before[static_cast<std::size_t>(stage)] + step,
                   steps_before.back());
      };
    if (options.holdout != nullptr && (options.holdout_free_run || options.holdout_horizon > 1)) {
      so.holdout = options.holdout;
      so.holdout_horizon = options.holdout_horizon;
      so.one_step_bound = options.holdout_one_step_bound;
    }
    report.simulation = TrainOnSimulationError(model, train, so).kept;
  }
  if (options.fit_envelope) model.envelope_ = DataEnvelope::Fit(model.models_, xs, ys);
  return report;
}

}  // namespace odonata::sysid

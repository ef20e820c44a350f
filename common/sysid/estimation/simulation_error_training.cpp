// Simulation-error training (docs/identifier.md §12): stages of iRprop− or Levenberg–Marquardt
// steps on the loss of simulation_loss.cpp, the hold-out keeping the best.

#include "sysid/estimation/simulation_error_training.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "sysid/estimation/rprop.hpp"
#include "sysid/estimation/stacked_parameters.hpp"

namespace odonata::sysid {
namespace {

constexpr double kPremiseStep = 0.01;     // initial iRprop− steps, scaled units
constexpr double kConsequentStep = 1e-3;  // smaller: a feedback coefficient near 1 is touchy
// The most parameters a Levenberg–Marquardt stage moves (docs/identifier.md §12).
constexpr Eigen::Index kMaxLevenbergMarquardtParameters = 256;

// Sets every output's consequent parameters from the stacked vector.
void SetConsequents(NarxModel& model, const Eigen::VectorXd& theta) {
  Eigen::Index at = 0;
  for (int o = 0; o < model.outputs(); ++o) {
    auto& c = model.mutable_model(o).mutable_consequent();
    const Eigen::Index size = c.Parameters().size();
    c.SetParameters(theta.segment(at, size));
    at += size;
  }
}

// Moves every output's parameters by the stacked step (ParameterOffsets' layout).
void StepParameters(NarxModel& model, const Eigen::VectorXd& delta, bool premises) {
  Eigen::Index at = 0;
  for (int o = 0; o < model.outputs(); ++o) {
    auto& m = model.mutable_model(o);
    auto& c = m.mutable_consequent();
    const Eigen::Index q = c.Parameters().size();
    c.SetParameters(c.Parameters() + delta.segment(at, q));
    at += q;
    if (!premises) continue;
    const Eigen::Index r = m.rules(), n = model.spec().size();
    const Eigen::ArrayXXd dc = Eigen::Map<const Eigen::ArrayXXd>(delta.data() + at, r, n);
    const Eigen::ArrayXXd ds = Eigen::Map<const Eigen::ArrayXXd>(delta.data() + at + r * n, r, n);
    m.StepPremises(dc, ds);
    at += 2 * r * n;
  }
}

// Every output's consequent is linear (Takagi–Sugeno): the linear model is one of its settings.
bool AllLinear(const NarxModel& model) {
  for (int o = 0; o < model.outputs(); ++o)
    if (model.model(o).consequent().kind() != fuzzy::ConsequentKind::kLinear) return false;
  return true;
}

// T with θ = T g: every rule of every output takes the same output's shared consequent g_o
// (inputs + 1 each, stacked in output order).
Eigen::MatrixXd TieRules(const NarxModel& model) {
  const Eigen::Index w = model.spec().size() + 1;
  const std::vector<Eigen::Index> offset = ParameterOffsets(model, false);
  Eigen::MatrixXd t = Eigen::MatrixXd::Zero(offset.back(), w * model.outputs());
  for (int o = 0; o < model.outputs(); ++o)
    for (int j = 0; j < model.model(o).rules(); ++j)
      t.block(offset[static_cast<std::size_t>(o)] + j * w, o * w, w, w).setIdentity();
  return t;
}

// The global linear model's one-step least-squares consequents (T's layout), in scaled units.
Eigen::VectorXd LinearLeastSquares(const NarxModel& model, const Series& series) {
  const RegressionData d = BuildRegression(model.spec(), series);
  const Eigen::Index n = model.spec().size();
  Eigen::MatrixXd z(d.x.rows(), n + 1);
  for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
    z(k, 0) = 1.0;
    z.row(k).tail(n) = model.scaling().ScaleRegressor(d.x.row(k).transpose()).transpose();
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(z);
  Eigen::VectorXd g(model.outputs() * (n + 1));
  for (int o = 0; o < model.outputs(); ++o) {
    Eigen::VectorXd y(d.x.rows());
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) y(k) = model.scaling().ScaleOutput(o, d.y(k, o));
    g.segment(o * (n + 1), n + 1) = qr.solve(y);
  }
  return g;
}

// Premises join the Levenberg–Marquardt step when some output has more than one rule: with one,
// the normalised firing is 1 wherever the centre, and their columns of J would be zero.
bool HasPremisesToFit(const NarxModel& model) {
  for (int o = 0; o < model.outputs(); ++o)
    if (model.model(o).rules() > 1) return true;
  return false;
}

}  // namespace

std::vector<SimulationStage> DefaultSimulationStages() {
  return {{10, 30}, {40, 30}, {160, 30}, {640, 30}};
}

namespace {

// One simulation-error training: the stages in order, each by Levenberg–Marquardt or iRprop−,
// the hold-out keeping the best parameters and the schedule that reaches them.
class SimulationTrainer {
 public:
  SimulationTrainer(NarxModel& model, const Series& train, const SimulationTrainOptions& options)
      : model_(model), train_(train), options_(options), kept_(model) {
    best_holdout_ = options.holdout ? model.NdeiAhead(*options.holdout, options.holdout_horizon)
                                    : std::numeric_limits<double>::infinity();
    // Beyond the longest run of consecutive targets a longer window is the same loss.
    const auto targets = TargetRows(model.spec(), train);
    std::size_t run = 0;
    for (std::size_t r = 0; r < targets.size(); ++r) {
      run = r > 0 && targets[r] == targets[r - 1] + 1 ? run + 1 : 1;
      longest_ = std::max(longest_, run);
    }
  }

  SimulationTrainReport Run() {
    int previous_horizon = 0;
    for (std::size_t stage = 0; stage < options_.stages.size(); ++stage) {
      const int horizon = std::min(options_.stages[stage].horizon,
                                   static_cast<int>(std::max<std::size_t>(longest_, 1)));
      if (horizon == previous_horizon && !options_.stages[stage].gauss_newton) break;
      previous_horizon = horizon;
      if (options_.stages[stage].gauss_newton)
        LevenbergMarquardtStage(stage, horizon);
      else
        RpropStage(stage, horizon);
    }
    if (options_.holdout) {
      model_ = kept_;
    } else {
      report_.kept = taken_;
    }
    return report_;
  }

 private:
  // After each step of either optimiser: progress and, with a hold-out, its score (the best
  // parameters and the schedule that reaches them kept). True when the stage's patience is out.
  bool AfterStep(std::size_t stage, int step) {
    if (options_.progress)
      options_.progress(static_cast<int>(stage), step, options_.stages[stage].steps);
    if (!options_.holdout) return false;
    const double h = model_.NdeiAhead(*options_.holdout, options_.holdout_horizon);
    report_.holdout_ndei.push_back(h);
    if (h < best_holdout_ && (std::isinf(options_.one_step_bound) ||
                              model_.NdeiAhead(*options_.holdout, 1) <= options_.one_step_bound)) {
      best_holdout_ = h;
      kept_ = model_;
      report_.kept = taken_;
      since_improvement_ = 0;
      return false;
    }
    return options_.patience > 0 && ++since_improvement_ >= options_.patience;
  }

  // Levenberg–Marquardt: the damping μ scales JᵀJ's diagonal, shrinks after a step that
  // lowers the loss and grows after one that does not (undone). On every parameter, or, from
  // the linear model, on the consequent every rule shares (J T for J).
  void LevenbergMarquardtStage(std::size_t stage, int horizon) {
    const bool tied = options_.stages[stage].from_linear;
    if (tied && !AllLinear(model_)) return;
    // JᵀJ costs samples × parameters² an iteration: a rule base too large for it takes the
    // consequents alone, and one whose consequents alone are too many passes the stage.
    const bool premises = !tied && HasPremisesToFit(model_) &&
                          ParameterOffsets(model_, true).back() <= kMaxLevenbergMarquardtParameters;
    if (!tied && ParameterOffsets(model_, premises).back() > kMaxLevenbergMarquardtParameters)
      return;
    const Eigen::MatrixXd tie = tied ? TieRules(model_) : Eigen::MatrixXd();
    const auto normal_equations = [&](const NarxModel& m, Eigen::MatrixXd& jtj,
                                      Eigen::VectorXd& jte) {
      return NormalEquations(m, train_, horizon, premises, jtj, jte, tied ? &tie : nullptr);
    };
    Eigen::VectorXd shared;
    if (tied) {
      shared = LinearLeastSquares(model_, train_);
      SetConsequents(model_, tie * shared);
    }
    Eigen::MatrixXd a;
    Eigen::VectorXd b;
    double loss = normal_equations(model_, a, b);
    if (stage == 0) report_.initial_loss = loss;
    taken_.push_back({horizon, 0, true, tied});
    if (!std::isfinite(loss)) return;
    double mu = 100.0;
    since_improvement_ = 0;
    for (int step = 1; step <= options_.stages[stage].steps; ++step) {
      bool converged = false;
      Eigen::MatrixXd m = a;
      m.diagonal().array() += mu * (a.diagonal().array() + 1e-12);
      const Eigen::VectorXd delta = m.ldlt().solve(-b);
      NarxModel trial = model_;
      if (tied) {
        SetConsequents(trial, tie * (shared + delta));
      } else {
        StepParameters(trial, delta, premises);
      }
      Eigen::MatrixXd a_new;
      Eigen::VectorXd b_new;
      const double trial_loss = normal_equations(trial, a_new, b_new);
      taken_.back().steps = step;
      const bool better = delta.allFinite() && trial_loss < loss;
      if (better) {
        const double gain = loss - trial_loss;
        model_ = std::move(trial);
        if (tied) shared += delta;
        a = std::move(a_new);
        b = std::move(b_new);
        mu = std::max(mu / 3.0, 1e-12);
        loss = trial_loss;
        converged = gain <= 1e-12 * loss;
      } else {
        mu *= 4.0;
      }
      // From the linear model, the stage is a start for the stages after it: it runs to its
      // optimum, the hold-out still keeping its best step.
      if ((AfterStep(stage, step) && !tied) || converged || mu > 1e12) break;
    }
  }

  // iRprop− on every parameter, a failed step undone with smaller steps.
  void RpropStage(std::size_t stage, int horizon) {
    const int no = model_.outputs();
    SimulationGradient g;
    double best = SimulationLoss(model_, train_, horizon, &g);
    if (stage == 0) report_.initial_loss = best;
    taken_.push_back({horizon, 0});
    if (!std::isfinite(best)) return;  // this window is too long for the model yet
    std::vector<Rprop> rc(static_cast<std::size_t>(no)), rs(rc), rq(rc);
    for (int o = 0; o < no; ++o) {
      const auto k = static_cast<std::size_t>(o);
      rc[k].Reset(g.centres[k].rows(), g.centres[k].cols(), kPremiseStep);
      rs[k].Reset(g.sigmas[k].rows(), g.sigmas[k].cols(), kPremiseStep);
      rq[k].Reset(g.consequents[k].size(), 1, kConsequentStep);
    }
    since_improvement_ = 0;
    for (int step = 1; step <= options_.stages[stage].steps; ++step) {
      const NarxModel before = model_;
      for (int o = 0; o < no; ++o) {
        const auto k = static_cast<std::size_t>(o);
        auto& m = model_.mutable_model(o);
        m.StepPremises(rc[k].Step(g.centres[k]), rs[k].Step(g.sigmas[k]));
        const Eigen::ArrayXXd dq = rq[k].Step(g.consequents[k].array());
        m.mutable_consequent().SetParameters(m.consequent().Parameters() + dq.matrix().col(0));
      }
      SimulationGradient g_new;
      const double loss = SimulationLoss(model_, train_, horizon, &g_new);
      taken_.back().steps = step;
      if (loss < best) {
        best = loss;
        g = std::move(g_new);
      } else {
        model_ = before;  // undo; smaller steps, and the kept parameters' gradient stands
        for (auto* r : {&rc, &rs, &rq})
          for (auto& x : *r) x.Backtrack();
      }
      if (AfterStep(stage, step)) break;
    }
  }

  NarxModel& model_;
  const Series& train_;
  const SimulationTrainOptions& options_;
  SimulationTrainReport report_;
  double best_holdout_ = 0;
  NarxModel kept_;                      // the parameters the hold-out prefers
  std::vector<SimulationStage> taken_;  // the schedule so far
  std::size_t longest_ = 0;             // the longest run of consecutive targets
  int since_improvement_ = 0;           // steps of the stage since the hold-out last improved
};

}  // namespace

SimulationTrainReport TrainOnSimulationError(NarxModel& model, const Series& train,
                                             const SimulationTrainOptions& options) {
  if (model.spec().output_lags < 1)
    throw std::invalid_argument("simulation-error training needs output lags");
  for (const auto& st : options.stages)
    if (st.horizon < 1 || st.steps < 0)
      throw std::invalid_argument("simulation stages need horizon >= 1 and steps >= 0");
  return SimulationTrainer(model, train, options).Run();
}

}  // namespace odonata::sysid

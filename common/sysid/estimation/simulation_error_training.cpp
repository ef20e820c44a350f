#include "sysid/estimation/simulation_error_training.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "sysid/estimation/rprop.hpp"

namespace odonata::sysid {
namespace {

constexpr double kPremiseStep = 0.01;     // initial iRprop− steps, scaled units
constexpr double kConsequentStep = 1e-3;  // smaller: a feedback coefficient near 1 is touchy
// The most parameters a Levenberg–Marquardt stage moves (docs/identifier.md §12).
constexpr Eigen::Index kMaxLevenbergMarquardtParameters = 256;
// A simulated output this many standard deviations away has left the data: the loss is +∞.
constexpr double kDiverged = 1e6;

// The windows: runs of consecutive target rows, cut every `horizon` targets.
std::vector<std::pair<std::size_t, std::size_t>> Windows(const std::vector<Eigen::Index>& targets,
                                                         int horizon) {
  std::vector<std::pair<std::size_t, std::size_t>> w;
  std::size_t begin = 0;
  for (std::size_t r = 1; r <= targets.size(); ++r) {
    const bool seam = r == targets.size() || targets[r] != targets[r - 1] + 1;
    if (seam || r - begin == static_cast<std::size_t>(horizon)) {
      w.emplace_back(begin, r);
      begin = r;
    }
  }
  return w;
}

// d x_s(regressor of output o, lag k + 1) / d ŷ_s(o), outputs × lags: the output's scale over
// the regressor's, what a simulated lag passes back (or forward) through the scaling.
Eigen::MatrixXd LagChain(const NarxModel& model) {
  const Scaling& sc = model.scaling();
  const int lags = model.spec().output_lags;
  Eigen::MatrixXd chain(model.outputs(), lags);
  for (int o = 0; o < model.outputs(); ++o)
    for (int k = 0; k < lags; ++k) chain(o, k) = sc.output_std(o) / sc.regressor_half(o * lags + k);
  return chain;
}

// Where each output's parameters start in the stacked vector: its consequents, then (with
// `premises`) its centres and its widths, rules × inputs each, column by column.
std::vector<Eigen::Index> ParameterOffsets(const NarxModel& model, bool premises) {
  std::vector<Eigen::Index> offset(static_cast<std::size_t>(model.outputs()) + 1, 0);
  for (int o = 0; o < model.outputs(); ++o) {
    const auto& m = model.model(o);
    Eigen::Index size = m.consequent().Parameters().size();
    if (premises) size += 2 * Eigen::Index{m.rules()} * model.spec().size();
    offset[static_cast<std::size_t>(o) + 1] = offset[static_cast<std::size_t>(o)] + size;
  }
  return offset;
}

}  // namespace

double SimulationLoss(const NarxModel& model, const Series& series, int horizon,
                      SimulationGradient* gradient) {
  const RegressorSpec& spec = model.spec();
  if (spec.output_lags < 1) throw std::invalid_argument("simulation error needs output lags");
  if (horizon < 1) throw std::invalid_argument("simulation horizon must be >= 1");
  const Scaling& sc = model.scaling();
  const int no = model.outputs();
  const int n = spec.size();
  const int lags = spec.output_lags;
  const auto targets = TargetRows(spec, series);
  if (gradient) {
    gradient->centres.clear();
    gradient->sigmas.clear();
    gradient->consequents.clear();
    for (int o = 0; o < no; ++o) {
      const auto& m = model.model(o);
      gradient->centres.push_back(Eigen::ArrayXXd::Zero(m.rules(), n));
      gradient->sigmas.push_back(Eigen::ArrayXXd::Zero(m.rules(), n));
      gradient->consequents.push_back(Eigen::VectorXd::Zero(m.consequent().Parameters().size()));
    }
  }
  const Eigen::MatrixXd chain = LagChain(model);

  Eigen::MatrixXd simulated = series.outputs;  // raw; each window restores what it overwrote
  Eigen::VectorXd raw(n);
  double loss = 0.0;
  const auto windows = Windows(targets, horizon);
  std::size_t longest = 0;
  for (const auto& [b, e] : windows) longest = std::max(longest, e - b);
  Eigen::MatrixXd xs(n, static_cast<Eigen::Index>(longest));  // scaled regressor per step
  std::vector<Eigen::MatrixXd> dydx(static_cast<std::size_t>(no),
                                    Eigen::MatrixXd(n, static_cast<Eigen::Index>(longest)));
  Eigen::MatrixXd err(no, static_cast<Eigen::Index>(longest));
  Eigen::MatrixXd delta(no, static_cast<Eigen::Index>(longest));
  Eigen::Array<bool, Eigen::Dynamic, Eigen::Dynamic> held(no, static_cast<Eigen::Index>(longest));
  const OutputLimits& limits = model.limits();
  for (const auto& [b, e] : windows) {
    const auto len = static_cast<Eigen::Index>(e - b);
    bool diverged = false;
    for (Eigen::Index s = 0; s < len; ++s) {
      const Eigen::Index t = targets[b + static_cast<std::size_t>(s)];
      spec.Fill(t, simulated, series.inputs, raw);
      xs.col(s) = sc.ScaleRegressor(raw);
      for (int o = 0; o < no; ++o) {
        const double ys = model.model(o).PredictWithInputGradient(
            xs.col(s), dydx[static_cast<std::size_t>(o)].col(s));
        const double target = sc.ScaleOutput(o, series.outputs(t, o));
        if (!std::isfinite(ys) || std::abs(ys) > kDiverged) diverged = true;
        // Held at a saturation limit, the output no longer moves with the parameters: nothing
        // flows back through it, to them or to earlier steps.
        const double raw_y = sc.UnscaleOutput(o, ys);
        held(o, s) = limits.Holds(o, raw_y);
        simulated(t, o) = limits.Apply(o, raw_y);
        err(o, s) = (held(o, s) ? sc.ScaleOutput(o, simulated(t, o)) : ys) - target;
      }
      if (diverged) break;
    }
    for (Eigen::Index s = 0; s < len; ++s) {  // the next window starts from measured outputs
      const Eigen::Index t = targets[b + static_cast<std::size_t>(s)];
      simulated.row(t) = series.outputs.row(t);
    }
    if (diverged) return std::numeric_limits<double>::infinity();
    loss += err.leftCols(len).squaredNorm();
    if (!gradient) continue;
    // Backwards through the window: ∂L/∂ŷ(t) is its own error plus what every later step that
    // read ŷ(t) as a lag passes back.
    for (Eigen::Index s = len - 1; s >= 0; --s) {
      for (int o = 0; o < no; ++o) {
        double d = 2.0 * err(o, s);
        for (int k = 1; k <= lags && s + k < len; ++k) {
          const Eigen::Index lag_index = o * lags + (k - 1);
          for (int p = 0; p < no; ++p)
            d += delta(p, s + k) * dydx[static_cast<std::size_t>(p)](lag_index, s + k) *
                 chain(o, k - 1);
        }
        delta(o, s) = held(o, s) ? 0.0 : d;
      }
      for (int o = 0; o < no; ++o) {
        model.model(o).AccumulateOutputGradient(
            xs.col(s), delta(o, s), &gradient->centres[static_cast<std::size_t>(o)],
            &gradient->sigmas[static_cast<std::size_t>(o)],
            &gradient->consequents[static_cast<std::size_t>(o)]);
      }
    }
  }
  return loss;
}

double NormalEquations(const NarxModel& model, const Series& series, int horizon, bool premises,
                       Eigen::MatrixXd& jtj, Eigen::VectorXd& jte, const Eigen::MatrixXd* tie) {
  const RegressorSpec& spec = model.spec();
  if (spec.output_lags < 1) throw std::invalid_argument("simulation error needs output lags");
  if (horizon < 1) throw std::invalid_argument("simulation horizon must be >= 1");
  const Scaling& sc = model.scaling();
  const OutputLimits& limits = model.limits();
  const int no = model.outputs();
  const int n = spec.size();
  const int lags = spec.output_lags;
  const std::vector<Eigen::Index> offset = ParameterOffsets(model, premises);
  if (tie && (premises || tie->rows() != offset.back()))
    throw std::invalid_argument("a tie maps the consequents alone");
  // Tied, the sensitivities are taken in the shared parameters: S T follows the same linear
  // recursion as S.
  const Eigen::Index np = tie ? tie->cols() : offset.back();
  jtj = Eigen::MatrixXd::Zero(np, np);
  jte = Eigen::VectorXd::Zero(np);
  const Eigen::MatrixXd chain = LagChain(model);
  const auto targets = TargetRows(spec, series);
  const auto windows = Windows(targets, horizon);
  std::size_t longest = 0;
  for (const auto& [b, e] : windows) longest = std::max(longest, e - b);
  // sens[s] = ∂ŷ(step s)/∂θ, outputs × parameters, scaled units.
  std::vector<Eigen::MatrixXd> sens(longest, Eigen::MatrixXd(no, np));
  Eigen::MatrixXd simulated = series.outputs;
  Eigen::VectorXd raw(n), xs(n), dydx(n);
  std::vector<Eigen::ArrayXXd> gc, gs;  // ∂ŷ/∂centres, ∂ŷ/∂widths at one step (rules × inputs)
  for (int o = 0; o < no && premises; ++o) {
    gc.push_back(Eigen::ArrayXXd::Zero(model.model(o).rules(), n));
    gs.push_back(gc.back());
  }
  double loss = 0.0;
  for (const auto& [b, e] : windows) {
    const auto len = static_cast<Eigen::Index>(e - b);
    bool diverged = false;
    for (Eigen::Index s = 0; s < len && !diverged; ++s) {
      const Eigen::Index t = targets[b + static_cast<std::size_t>(s)];
      spec.Fill(t, simulated, series.inputs, raw);
      xs = sc.ScaleRegressor(raw);
      Eigen::MatrixXd& S = sens[static_cast<std::size_t>(s)];
      S.setZero();
      for (int o = 0; o < no; ++o) {
        const auto& m = model.model(o);
        const double ys = m.PredictWithInputGradient(xs, dydx);
        if (!std::isfinite(ys) || std::abs(ys) > kDiverged) {
          diverged = true;
          break;
        }
        const double raw_y = sc.UnscaleOutput(o, ys);
        const double target = sc.ScaleOutput(o, series.outputs(t, o));
        simulated(t, o) = limits.Apply(o, raw_y);
        const double e_o = sc.ScaleOutput(o, simulated(t, o)) - target;
        loss += e_o * e_o;
        if (limits.Holds(o, raw_y)) continue;  // held: no sensitivity
        const auto k_o = static_cast<std::size_t>(o);
        const Eigen::Index q = m.consequent().Parameters().size();
        Eigen::VectorXd direct = Eigen::VectorXd::Zero(q);
        if (premises) {
          gc[k_o].setZero();
          gs[k_o].setZero();
        }
        m.AccumulateOutputGradient(xs, 1.0, premises ? &gc[k_o] : nullptr,
                                   premises ? &gs[k_o] : nullptr, &direct);
        if (tie) {
          S.row(o) = direct.transpose() * tie->middleRows(offset[k_o], q);
        } else {
          S.row(o).segment(offset[k_o], q) = direct.transpose();
        }
        if (premises) {
          const Eigen::Index rn = gc[k_o].size();
          S.row(o).segment(offset[k_o] + q, rn) =
              Eigen::Map<const Eigen::RowVectorXd>(gc[k_o].data(), rn);
          S.row(o).segment(offset[k_o] + q + rn, rn) =
              Eigen::Map<const Eigen::RowVectorXd>(gs[k_o].data(), rn);
        }
        for (int k = 1; k <= lags && s - k >= 0; ++k)
          for (int p = 0; p < no; ++p)
            S.row(o) += dydx(p * lags + (k - 1)) * chain(p, k - 1) *
                        sens[static_cast<std::size_t>(s - k)].row(p);
        jtj.selfadjointView<Eigen::Lower>().rankUpdate(S.row(o).transpose());
        jte += S.row(o).transpose() * e_o;
      }
    }
    for (Eigen::Index s = 0; s < len; ++s) {
      const Eigen::Index t = targets[b + static_cast<std::size_t>(s)];
      simulated.row(t) = series.outputs.row(t);
    }
    if (diverged) return std::numeric_limits<double>::infinity();
  }
  jtj = jtj.selfadjointView<Eigen::Lower>();
  return loss;
}

namespace {

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

SimulationTrainReport TrainOnSimulationError(NarxModel& model, const Series& train,
                                             const SimulationTrainOptions& options) {
  if (model.spec().output_lags < 1)
    throw std::invalid_argument("simulation-error training needs output lags");
  for (const auto& st : options.stages)
    if (st.horizon < 1 || st.steps < 0)
      throw std::invalid_argument("simulation stages need horizon >= 1 and steps >= 0");
  SimulationTrainReport report;
  const int no = model.outputs();
  double best_holdout = options.holdout ? model.NdeiAhead(*options.holdout, options.holdout_horizon)
                                        : std::numeric_limits<double>::infinity();
  NarxModel kept = model;              // the parameters the hold-out prefers
  std::vector<SimulationStage> taken;  // the schedule so far
  // Beyond the longest run of consecutive targets a longer window is the same loss.
  const auto targets = TargetRows(model.spec(), train);
  std::size_t longest = 0, run = 0;
  for (std::size_t r = 0; r < targets.size(); ++r) {
    run = r > 0 && targets[r] == targets[r - 1] + 1 ? run + 1 : 1;
    longest = std::max(longest, run);
  }
  int since_improvement = 0;  // steps of the stage since the hold-out last improved
  // After each step of either optimiser: progress and, with a hold-out, its score (the best
  // parameters and the schedule that reaches them kept). True when the stage's patience is out.
  const auto after_step = [&](std::size_t stage, int step) {
    if (options.progress)
      options.progress(static_cast<int>(stage), step, options.stages[stage].steps);
    if (!options.holdout) return false;
    const double h = model.NdeiAhead(*options.holdout, options.holdout_horizon);
    report.holdout_ndei.push_back(h);
    if (h < best_holdout && (std::isinf(options.one_step_bound) ||
                             model.NdeiAhead(*options.holdout, 1) <= options.one_step_bound)) {
      best_holdout = h;
      kept = model;
      report.kept = taken;
      since_improvement = 0;
      return false;
    }
    return options.patience > 0 && ++since_improvement >= options.patience;
  };
  int previous_horizon = 0;
  for (std::size_t stage = 0; stage < options.stages.size(); ++stage) {
    const int horizon = std::min(options.stages[stage].horizon,
                                 static_cast<int>(std::max<std::size_t>(longest, 1)));
    if (horizon == previous_horizon && !options.stages[stage].gauss_newton) break;
    previous_horizon = horizon;
    if (options.stages[stage].gauss_newton) {
      // Levenberg–Marquardt: the damping μ scales JᵀJ's diagonal, shrinks after a step that
      // lowers the loss and grows after one that does not (undone). On every parameter, or, from
      // the linear model, on the consequent every rule shares (J T for J).
      const bool tied = options.stages[stage].from_linear;
      if (tied && !AllLinear(model)) continue;
      // JᵀJ costs samples × parameters² an iteration: a rule base too large for it takes the
      // consequents alone, and one whose consequents alone are too many passes the stage.
      const bool premises =
          !tied && HasPremisesToFit(model) &&
          ParameterOffsets(model, true).back() <= kMaxLevenbergMarquardtParameters;
      if (!tied && ParameterOffsets(model, premises).back() > kMaxLevenbergMarquardtParameters)
        continue;
      const Eigen::MatrixXd tie = tied ? TieRules(model) : Eigen::MatrixXd();
      const auto normal_equations = [&](const NarxModel& m, Eigen::MatrixXd& jtj,
                                        Eigen::VectorXd& jte) {
        return NormalEquations(m, train, horizon, premises, jtj, jte, tied ? &tie : nullptr);
      };
      Eigen::VectorXd shared;
      if (tied) {
        shared = LinearLeastSquares(model, train);
        SetConsequents(model, tie * shared);
      }
      Eigen::MatrixXd a;
      Eigen::VectorXd b;
      double loss = normal_equations(model, a, b);
      if (stage == 0) report.initial_loss = loss;
      taken.push_back({horizon, 0, true, tied});
      if (!std::isfinite(loss)) continue;
      double mu = 100.0;
      since_improvement = 0;
      for (int step = 1; step <= options.stages[stage].steps; ++step) {
        bool converged = false;
        Eigen::MatrixXd m = a;
        m.diagonal().array() += mu * (a.diagonal().array() + 1e-12);
        const Eigen::VectorXd delta = m.ldlt().solve(-b);
        NarxModel trial = model;
        if (tied) {
          SetConsequents(trial, tie * (shared + delta));
        } else {
          StepParameters(trial, delta, premises);
        }
        Eigen::MatrixXd a_new;
        Eigen::VectorXd b_new;
        const double trial_loss = normal_equations(trial, a_new, b_new);
        taken.back().steps = step;
        const bool better = delta.allFinite() && trial_loss < loss;
        if (better) {
          const double gain = loss - trial_loss;
          model = std::move(trial);
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
        if ((after_step(stage, step) && !tied) || converged || mu > 1e12) break;
      }
      continue;
    }
    SimulationGradient g;
    double best = SimulationLoss(model, train, horizon, &g);
    if (stage == 0) report.initial_loss = best;
    taken.push_back({horizon, 0});
    if (!std::isfinite(best)) continue;  // this window is too long for the model yet
    std::vector<Rprop> rc(static_cast<std::size_t>(no)), rs(rc), rq(rc);
    for (int o = 0; o < no; ++o) {
      const auto k = static_cast<std::size_t>(o);
      rc[k].Reset(g.centres[k].rows(), g.centres[k].cols(), kPremiseStep);
      rs[k].Reset(g.sigmas[k].rows(), g.sigmas[k].cols(), kPremiseStep);
      rq[k].Reset(g.consequents[k].size(), 1, kConsequentStep);
    }
    since_improvement = 0;
    for (int step = 1; step <= options.stages[stage].steps; ++step) {
      const NarxModel before = model;
      for (int o = 0; o < no; ++o) {
        const auto k = static_cast<std::size_t>(o);
        auto& m = model.mutable_model(o);
        m.StepPremises(rc[k].Step(g.centres[k]), rs[k].Step(g.sigmas[k]));
        const Eigen::ArrayXXd dq = rq[k].Step(g.consequents[k].array());
        m.mutable_consequent().SetParameters(m.consequent().Parameters() + dq.matrix().col(0));
      }
      SimulationGradient g_new;
      const double loss = SimulationLoss(model, train, horizon, &g_new);
      taken.back().steps = step;
      if (loss < best) {
        best = loss;
        g = std::move(g_new);
      } else {
        model = before;  // undo; smaller steps, and the kept parameters' gradient stands
        for (auto* r : {&rc, &rs, &rq})
          for (auto& x : *r) x.Backtrack();
      }
      if (after_step(stage, step)) break;
    }
  }
  if (options.holdout) {
    model = kept;
  } else {
    report.kept = taken;
  }
  return report;
}

}  // namespace odonata::sysid

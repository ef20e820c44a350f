#include "sysid/simulation_error_training.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "sysid/rprop.hpp"

namespace odonata::sysid {
namespace {

constexpr double kPremiseStep = 0.01;     // initial iRprop− steps, scaled units
constexpr double kConsequentStep = 1e-3;  // smaller: a feedback coefficient near 1 is touchy
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
  // d x_s(regressor of output o, lag k) / d ŷ_s(o): the output's scale over the regressor's.
  Eigen::MatrixXd chain(no, lags);
  for (int o = 0; o < no; ++o)
    for (int k = 0; k < lags; ++k) chain(o, k) = sc.output_std(o) / sc.regressor_half(o * lags + k);

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
        err(o, s) = ys - target;
        if (!std::isfinite(ys) || std::abs(ys) > kDiverged) diverged = true;
        simulated(t, o) = sc.UnscaleOutput(o, ys);
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
        delta(o, s) = d;
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
  int previous_horizon = 0;
  for (std::size_t stage = 0; stage < options.stages.size(); ++stage) {
    const int horizon = std::min(options.stages[stage].horizon,
                                 static_cast<int>(std::max<std::size_t>(longest, 1)));
    if (horizon == previous_horizon) break;
    previous_horizon = horizon;
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
    int since_improvement = 0;
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
      if (options.progress)
        options.progress(static_cast<int>(stage), step, options.stages[stage].steps);
      if (!options.holdout) continue;
      const double h = model.NdeiAhead(*options.holdout, options.holdout_horizon);
      report.holdout_ndei.push_back(h);
      if (h < best_holdout) {
        best_holdout = h;
        kept = model;
        report.kept = taken;
        since_improvement = 0;
      } else if (options.patience > 0 && ++since_improvement >= options.patience) {
        break;
      }
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

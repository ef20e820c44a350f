// The simulation error and its derivatives: the loss iRprop− descends (with its gradient) and
// the normal equations of a Levenberg–Marquardt step, over windows of consecutive targets each
// started from measured outputs.

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "sysid/estimation/simulation_error_training.hpp"
#include "sysid/estimation/stacked_parameters.hpp"

namespace odonata::sysid {
namespace {

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

}  // namespace

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

}  // namespace odonata::sysid

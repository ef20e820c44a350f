#include "sysid/model/local_dynamics.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <optional>

#include <Eigen/Eigenvalues>
#include <nlohmann/json.hpp>

#include "fuzzy/linear_consequent.hpp"
#include "fuzzy/singleton_consequent.hpp"
#include "io/json_number.hpp"

namespace odonata::sysid {
namespace {

std::string FourDigits(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.4g", v);
  return b;
}

}  // namespace

namespace {
// Each exogenous signal's lags in the regressor, with its coefficient column: the other outputs
// at 1 … n, then each input at d … d+m−1 (RegressorSpec::Fill).
struct Exogenous {
  std::string name;
  std::vector<std::pair<int, Eigen::Index>> lags;  // (lag, regressor column)
  int longest() const {
    int p = 0;
    for (const auto& l : lags) p = std::max(p, l.first);
    return p;
  }
};
std::vector<Exogenous> ExogenousSignals(const RegressorSpec& spec, int output) {
  std::vector<Exogenous> e;
  const int n = spec.output_lags;
  for (std::size_t o = 0; o < spec.outputs.size(); ++o) {
    if (static_cast<int>(o) == output || n == 0) continue;
    Exogenous x{spec.outputs[o], {}};
    for (int l = 1; l <= n; ++l) x.lags.emplace_back(l, static_cast<Eigen::Index>(o) * n + l - 1);
    e.push_back(x);
  }
  const Eigen::Index first = static_cast<Eigen::Index>(spec.outputs.size()) * n;
  for (std::size_t i = 0; i < spec.inputs.size(); ++i) {
    Exogenous x{spec.inputs[i], {}};
    for (int l = 0; l < spec.input_lags; ++l)
      x.lags.emplace_back(spec.delay + l,
                          first + static_cast<Eigen::Index>(i) * spec.input_lags + l);
    e.push_back(x);
  }
  return e;
}
}  // namespace

RawLinearModel RuleLinearModel(const NarxModel& model, int output, int rule) {
  const auto& fm = model.model(output);
  const auto& sc = model.scaling();
  RawLinearModel m;
  m.coefficients = Eigen::VectorXd::Zero(fm.inputs());
  if (fm.consequent().kind() == fuzzy::ConsequentKind::kSingleton) {
    const auto& cons = static_cast<const fuzzy::SingletonConsequent&>(fm.consequent());
    m.constant = sc.UnscaleOutput(output, cons.centre(rule));
    return m;
  }
  const auto& cons = static_cast<const fuzzy::LinearConsequent&>(fm.consequent());
  return ScaledToRaw(sc, output, cons.coefficients(rule));
}

RawLinearModel ScaledToRaw(const Scaling& sc, int output, const Eigen::VectorXd& theta) {
  // y = mean + std (a0 + Σ a_i (r_i − mid_i)/half_i), expanded to raw coefficients.
  const auto n = theta.size() - 1;
  const double ys = sc.output_std(output);
  RawLinearModel m;
  m.coefficients = Eigen::VectorXd::Zero(n);
  m.constant = sc.output_mean(output) + ys * theta(0);
  for (Eigen::Index i = 0; i < n; ++i) {
    m.coefficients(i) = ys * theta(i + 1) / sc.regressor_half(i);
    m.constant -= m.coefficients(i) * sc.regressor_mid(i);
  }
  return m;
}

std::optional<RawLinearModel> GlobalLinearModel(const NarxModel& model, int output) {
  const DataEnvelope& e = model.envelope();
  if (!e.any()) return std::nullopt;
  return ScaledToRaw(model.scaling(), output,
                     e.outputs.at(static_cast<std::size_t>(output)).linear);
}

LocalDynamics AnalyseDynamics(const RegressorSpec& spec, int output, const RawLinearModel& model,
                              double sample_time_s) {
  LocalDynamics d;
  const int n = spec.output_lags;
  // The output's own lags: a_1 … a_n (regressor layout: RegressorSpec::Fill).
  Eigen::VectorXd a = Eigen::VectorXd::Zero(n);
  for (int l = 0; l < n; ++l) a(l) = model.coefficients(output * n + l);
  if (n > 0) {
    // Companion matrix of z^n − a_1 z^(n−1) − … − a_n: its eigenvalues are the poles.
    Eigen::MatrixXd c = Eigen::MatrixXd::Zero(n, n);
    c.row(0) = a.transpose();
    for (int r = 1; r < n; ++r) c(r, r - 1) = 1.0;
    const Eigen::VectorXcd p = Eigen::EigenSolver<Eigen::MatrixXd>(c, false).eigenvalues();
    for (Eigen::Index i = 0; i < p.size(); ++i) d.poles.push_back(p(i));
    // Slowest first: the pole that sets the time scale leads.
    std::sort(d.poles.begin(), d.poles.end(), [](const auto& x, const auto& y) {
      return std::abs(x) != std::abs(y) ? std::abs(x) > std::abs(y) : x.imag() > y.imag();
    });
  }
  const double t = sample_time_s > 0 ? sample_time_s : 1.0;
  for (const auto& p : d.poles) {
    const double r = std::abs(p);
    d.stable = d.stable && r < 1.0;
    if (r == 0.0) {
      d.time_constants.push_back(0.0);
      d.damping.push_back(1.0);
      continue;
    }
    const std::complex<double> s = std::log(p) / t;
    d.time_constants.push_back(s.real() == 0.0 ? std::numeric_limits<double>::infinity()
                                               : -1.0 / s.real());
    d.damping.push_back(-s.real() / std::abs(s));
  }
  const double rest = 1.0 - a.sum();  // A(1)
  const auto gain = [rest](double b) {
    return rest == 0.0 ? std::numeric_limits<double>::quiet_NaN() : b / rest;
  };
  d.equilibrium = gain(model.constant);
  // Each exogenous signal's coefficients summed over its lags.
  for (const auto& e : ExogenousSignals(spec, output)) {
    double b = 0;
    for (const auto& lag : e.lags) b += model.coefficients(lag.second);
    d.dc_gain.emplace_back(e.name, gain(b));
  }
  return d;
}

LocalStateSpace StateSpace(const RegressorSpec& spec, int output, const RawLinearModel& model) {
  const int n = spec.output_lags;
  const auto signals = ExogenousSignals(spec, output);
  int size = n;
  std::vector<int> start;  // each signal's first state: v(t−1)
  for (const auto& s : signals) {
    start.push_back(size);
    size += s.longest();
  }
  const auto m = static_cast<Eigen::Index>(signals.size());
  LocalStateSpace ss;
  ss.a = Eigen::MatrixXd::Zero(size, size);
  ss.b = Eigen::MatrixXd::Zero(size, m);
  ss.c = Eigen::MatrixXd::Zero(1, size);
  ss.d = Eigen::MatrixXd::Zero(1, m);
  ss.offset = model.constant;
  // y(t) = Σ a_l y(t−l) + Σ b_eλ v_e(t−λ): state y(t−l) at l−1, v_e(t−λ) at start_e + λ − 1.
  for (int l = 1; l <= n; ++l) ss.c(0, l - 1) = model.coefficients(output * n + l - 1);
  for (Eigen::Index e = 0; e < m; ++e) {
    ss.signals.push_back(signals[static_cast<std::size_t>(e)].name);
    for (const auto& [lag, col] : signals[static_cast<std::size_t>(e)].lags) {
      if (lag == 0)
        ss.d(0, e) = model.coefficients(col);
      else
        ss.c(0, start[static_cast<std::size_t>(e)] + lag - 1) = model.coefficients(col);
    }
  }
  // Next state: y(t) (= C x + D v) then the older lags shifted; each signal's v(t) then its own.
  if (n > 0) {
    ss.a.row(0) = ss.c;
    ss.b.row(0) = ss.d;
    for (int r = 1; r < n; ++r) ss.a(r, r - 1) = 1.0;
  }
  for (Eigen::Index e = 0; e < m; ++e) {
    const int s0 = start[static_cast<std::size_t>(e)];
    const int p = signals[static_cast<std::size_t>(e)].longest();
    if (p == 0) continue;
    ss.b(s0, e) = 1.0;
    for (int r = 1; r < p; ++r) ss.a(s0 + r, s0 + r - 1) = 1.0;
  }
  return ss;
}

std::vector<double> StepResponse(const RegressorSpec& spec, int output, const RawLinearModel& model,
                                 int signal, int steps) {
  const int n = spec.output_lags;
  const auto signals = ExogenousSignals(spec, output);
  const auto& lags = signals.at(static_cast<std::size_t>(signal)).lags;
  std::vector<double> y(static_cast<std::size_t>(steps), 0.0);
  for (int t = 0; t < steps; ++t) {
    double v = 0;
    for (int l = 1; l <= n && t - l >= 0; ++l)
      v += model.coefficients(output * n + l - 1) * y[static_cast<std::size_t>(t - l)];
    for (const auto& [lag, col] : lags)
      if (t - lag >= 0) v += model.coefficients(col);  // the step is 1 from t = 0 on
    y[static_cast<std::size_t>(t)] = v;
  }
  return y;
}

std::string SentenceNumber(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", v);
  return b;
}

std::vector<LocalDynamics> LocalModels(const NarxModel& model, int output, double sample_time_s) {
  std::vector<LocalDynamics> all;
  for (int j = 0; j < model.model(output).rules(); ++j)
    all.push_back(
        AnalyseDynamics(model.spec(), output, RuleLinearModel(model, output, j), sample_time_s));
  return all;
}

nlohmann::json ToJson(const LocalDynamics& d, double sample_time_s) {
  // JSON has no NaN or infinity: a gain with a pole at 1, or a pole on the unit circle, is null.
  const auto num = io::FiniteOrNull;
  nlohmann::json poles = nlohmann::json::array(), tau = nlohmann::json::array(),
                 zeta = nlohmann::json::array(), gains = nlohmann::json::object();
  for (std::size_t i = 0; i < d.poles.size(); ++i) {
    poles.push_back({d.poles[i].real(), d.poles[i].imag()});
    tau.push_back(num(d.time_constants[i]));
    zeta.push_back(num(d.damping[i]));
  }
  for (const auto& [name, g] : d.dc_gain) gains[name] = num(g);
  return {{"poles", poles},
          {"stable", d.stable},
          {sample_time_s > 0 ? "time_constants_s" : "time_constants_samples", tau},
          {"damping", zeta},
          {"dc_gain", gains},
          {"equilibrium", num(d.equilibrium)}};
}

std::string DescribeDynamics(const LocalDynamics& d, double sample_time_s) {
  std::string s;
  if (!d.poles.empty()) {
    const double tau = d.time_constants.front();
    const std::string unit = sample_time_s > 0 ? " s" : " samples";
    if (!d.stable)
      s = "unstable (pole " + FourDigits(std::abs(d.poles.front())) + ")";
    else
      s = "τ " + SentenceNumber(tau) + unit;
    if (d.poles.front().imag() != 0.0) s += ", damping " + SentenceNumber(d.damping.front());
  }
  for (const auto& [name, g] : d.dc_gain) {
    s += (s.empty() ? "gain " : (s.find("gain") == std::string::npos ? ", gain " : ", ")) +
         SentenceNumber(g) + " from " + name;
  }
  return s;
}

}  // namespace odonata::sysid

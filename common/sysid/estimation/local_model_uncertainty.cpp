#include "sysid/estimation/local_model_uncertainty.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "fuzzy/gaussian_rule_base.hpp"
#include "io/json_number.hpp"
#include "sysid/model/local_dynamics.hpp"

namespace odonata::sysid {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

Eigen::VectorXd Parameters(const RawLinearModel& m) {
  Eigen::VectorXd theta(m.coefficients.size() + 1);
  theta(0) = m.constant;
  theta.tail(m.coefficients.size()) = m.coefficients;
  return theta;
}

RawLinearModel FromParameters(const Eigen::VectorXd& theta) {
  RawLinearModel m;
  m.constant = theta(0);
  m.coefficients = theta.tail(theta.size() - 1);
  return m;
}

// What the readable form prints of θ, flattened: the time constants, then the gains.
Eigen::VectorXd Printed(const RegressorSpec& spec, int output, const Eigen::VectorXd& theta,
                        double sample_time_s) {
  const LocalDynamics d = AnalyseDynamics(spec, output, FromParameters(theta), sample_time_s);
  Eigen::VectorXd v(d.time_constants.size() + d.dc_gain.size());
  Eigen::Index i = 0;
  for (const double t : d.time_constants) v(i++) = t;
  for (const auto& g : d.dc_gain) v(i++) = g.second;
  return v;
}

// √(∇fᵀ Cov ∇f) for every printed quantity f, ∇f by central differences.
Eigen::VectorXd DeltaMethodSe(const RegressorSpec& spec, int output, const Eigen::VectorXd& theta,
                              const Eigen::MatrixXd& cov, double sample_time_s) {
  const Eigen::VectorXd f0 = Printed(spec, output, theta, sample_time_s);
  Eigen::MatrixXd jac(f0.size(), theta.size());
  for (Eigen::Index j = 0; j < theta.size(); ++j) {
    const double h = kDeltaStep * std::max(std::abs(theta(j)), 1e-3);
    Eigen::VectorXd up = theta, down = theta;
    up(j) += h;
    down(j) -= h;
    const Eigen::VectorXd fu = Printed(spec, output, up, sample_time_s);
    const Eigen::VectorXd fd = Printed(spec, output, down, sample_time_s);
    // A pole that changes its kind (real pair to complex) reorders the list: no derivative.
    jac.col(j) = fu.size() == f0.size() && fd.size() == f0.size()
                     ? Eigen::VectorXd((fu - fd) / (2 * h))
                     : Eigen::VectorXd::Constant(f0.size(), kNaN);
  }
  Eigen::VectorXd se(f0.size());
  for (Eigen::Index i = 0; i < f0.size(); ++i) {
    const double var = jac.row(i) * cov * jac.row(i).transpose();
    se(i) = var >= 0.0 ? std::sqrt(var) : kNaN;
  }
  return se;
}

}  // namespace

std::vector<LocalUncertainty> LocalModelUncertainty(const NarxModel& model, int output,
                                                    const Series& train, double sample_time_s) {
  const auto& fm = model.model(output);
  std::vector<LocalUncertainty> out;
  if (fm.consequent().kind() != fuzzy::ConsequentKind::kLinear || fm.rules() == 0) return out;
  const RegressionData d = BuildRegression(model.spec(), train);
  const int rules = fm.rules();
  const Eigen::Index p = d.x.cols() + 1;
  std::vector<Eigen::MatrixXd> a(rules, Eigen::MatrixXd::Zero(p, p)), c = a;
  std::vector<double> wsum(rules, 0.0), we2(rules, 0.0);
  fuzzy::Inference inf;
  Eigen::VectorXd phi(p);
  for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
    const Eigen::VectorXd x = d.x.row(k).transpose();
    const double e = d.y(k, output) - model.Predict(x)(output);
    fm.rule_base().Evaluate(model.scaling().ScaleRegressor(x), &inf);
    phi(0) = 1.0;
    phi.tail(p - 1) = x;
    const Eigen::MatrixXd outer = phi * phi.transpose();
    for (int j = 0; j < rules; ++j) {
      const double w = inf.normalized(j);
      if (!(w > 0.0)) continue;
      a[j] += w * outer;
      c[j] += w * w * outer;
      wsum[j] += w;
      we2[j] += w * e * e;
    }
  }
  for (int j = 0; j < rules; ++j) {
    LocalUncertainty u;
    u.effective_rows = wsum[j];
    const Eigen::VectorXd theta = Parameters(RuleLinearModel(model, output, j));
    const LocalDynamics dyn =
        AnalyseDynamics(model.spec(), output, FromParameters(theta), sample_time_s);
    u.time_constant_se.assign(dyn.time_constants.size(), kNaN);
    for (const auto& g : dyn.dc_gain) u.dc_gain_se.emplace_back(g.first, kNaN);
    const double dof = wsum[j] - static_cast<double>(p);
    const Eigen::LDLT<Eigen::MatrixXd> ldlt(a[j]);
    if (dof > 0.0 && ldlt.info() == Eigen::Success && ldlt.isPositive()) {
      const double sigma2 = we2[j] / dof;
      u.residual_std = std::sqrt(sigma2);
      const Eigen::MatrixXd ainv_c = ldlt.solve(c[j]);
      u.covariance = sigma2 * ldlt.solve(ainv_c.transpose()).transpose();
      const Eigen::VectorXd se =
          DeltaMethodSe(model.spec(), output, theta, u.covariance, sample_time_s);
      Eigen::Index i = 0;
      for (double& s : u.time_constant_se) s = se(i++);
      for (auto& g : u.dc_gain_se) g.second = se(i++);
    }
    out.push_back(std::move(u));
  }
  return out;
}

nlohmann::json ToJson(const LocalUncertainty& u, double sample_time_s) {
  const auto num = io::FiniteOrNull;
  nlohmann::json tau = nlohmann::json::array(), gains = nlohmann::json::object(),
                 cov = nlohmann::json::array();
  for (const double s : u.time_constant_se) tau.push_back(num(s));
  for (const auto& [name, s] : u.dc_gain_se) gains[name] = num(s);
  for (Eigen::Index r = 0; r < u.covariance.rows(); ++r) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index c = 0; c < u.covariance.cols(); ++c) row.push_back(num(u.covariance(r, c)));
    cov.push_back(std::move(row));
  }
  return {{"effective_rows", u.effective_rows},
          {"residual_std", num(u.residual_std)},
          {sample_time_s > 0 ? "time_constants_se_s" : "time_constants_se_samples", tau},
          {"dc_gain_se", gains},
          {"parameter_covariance", cov}};
}

nlohmann::json LocalCovariancesToJson(const NarxModel& model, const Series& train,
                                      double sample_time_s) {
  nlohmann::json all = nlohmann::json::object();
  for (int o = 0; o < model.outputs(); ++o) {
    const auto rules = LocalModelUncertainty(model, o, train, sample_time_s);
    if (rules.empty()) continue;
    nlohmann::json per_rule = nlohmann::json::array();
    for (const auto& u : rules) {
      const nlohmann::json j = ToJson(u, sample_time_s)["parameter_covariance"];
      per_rule.push_back(j.empty() ? nlohmann::json() : j);
    }
    all[model.spec().outputs[static_cast<std::size_t>(o)]] = per_rule;
  }
  return all.empty() ? nlohmann::json() : all;
}

std::string DescribeWithUncertainty(const RegressorSpec& spec, int output, const NarxModel& model,
                                    int rule, const LocalUncertainty& u, double sample_time_s) {
  const LocalDynamics d =
      AnalyseDynamics(spec, output, RuleLinearModel(model, output, rule), sample_time_s);
  const auto pm = [](double v, double se) {
    return SentenceNumber(v) + (std::isfinite(se) ? " ± " + SentenceNumber(se) : "");
  };
  std::string s;
  if (!d.time_constants.empty()) {
    std::size_t slow = 0;
    for (std::size_t i = 1; i < d.time_constants.size(); ++i)
      if (std::abs(d.time_constants[i]) > std::abs(d.time_constants[slow])) slow = i;
    s = "τ " + pm(d.time_constants[slow], u.time_constant_se[slow]) +
        (sample_time_s > 0 ? " s" : " samples");
  }
  for (std::size_t i = 0; i < d.dc_gain.size(); ++i)
    s += (s.empty() ? "gain " : (i == 0 ? ", gain " : ", ")) +
         pm(d.dc_gain[i].second, u.dc_gain_se[i].second) + " from " + d.dc_gain[i].first;
  s += " (" + std::to_string(std::llround(u.effective_rows)) + " rows)";
  return s;
}

}  // namespace odonata::sysid

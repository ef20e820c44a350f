#include "fit/local_spread.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <Eigen/Cholesky>

#include "fuzzy/gaussian_rule_base.hpp"
#include "sysid/model/free_run.hpp"

namespace odonata::fit {

LocalSpread LocalSpread::Fit(const sysid::NarxModel& model, const sysid::Series& train) {
  LocalSpread s;
  const sysid::RegressionData d = sysid::BuildRegression(model.spec(), train);
  // One-step residuals, every output at once (PredictOneStep's rows are BuildRegression's).
  const Eigen::MatrixXd residuals =
      d.y - sysid::PredictOneStep(model.spec(), train,
                                  [&model](const Eigen::VectorXd& x) { return model.Predict(x); });
  const int outputs = model.outputs();
  s.floor_ = Eigen::VectorXd::Zero(outputs);
  s.reach_ = Eigen::VectorXd::Zero(outputs);
  fuzzy::Inference inf;
  for (int o = 0; o < outputs; ++o) {
    const auto& fm = model.model(o);
    const int r = fm.rules();
    const double p = fm.consequent().LeastSquaresWidth();  // a rule's parameters
    Eigen::VectorXd n = Eigen::VectorXd::Zero(r), b = n;
    Eigen::MatrixXd g = Eigen::MatrixXd::Zero(r, r);
    std::vector<double> distances;
    double e2_sum = 0.0, e2_max = 0.0;
    Eigen::Index finite = 0;
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
      const double e = residuals(k, o);
      if (!std::isfinite(e)) continue;
      e2_sum += e * e;
      e2_max = std::max(e2_max, e * e);
      ++finite;
      if (r == 0) continue;
      fm.rule_base().Evaluate(model.scaling().ScaleRegressor(d.x.row(k).transpose()), &inf);
      const Eigen::VectorXd phi = inf.normalized.matrix().head(r);
      n += phi;
      g.selfadjointView<Eigen::Lower>().rankUpdate(phi);
      b += phi * (e * e);
      distances.push_back(inf.min_distance);
    }
    const double mean_e2 = finite > 0 ? e2_sum / double(finite) : 0.0;
    // The rules' squared residuals as a fuzzy model of e² on the same firings (least squares,
    // a relative ridge for rules that never fire apart): unblended where the firings overlap.
    Eigen::VectorXd c = Eigen::VectorXd::Zero(r);
    if (r > 0) {
      g.diagonal().array() += 1e-9 * g.diagonal().sum() / r + 1e-300;
      c = g.selfadjointView<Eigen::Lower>().ldlt().solve(b);
    }
    Eigen::VectorXd v(r);
    for (int j = 0; j < r; ++j)
      // A rule that stood for less than a row has no spread of its own: the output's, as wide as
      // one row allows. Its least-squares value is held within the squared residuals seen: a
      // rule that barely fires is barely determined.
      v(j) = n(j) >= 1.0 && std::isfinite(c(j)) ? std::clamp(c(j), 0.0, e2_max) * (1.0 + p / n(j))
                                                : mean_e2 * (1.0 + p);
    s.rule_variance_.push_back(v);
    s.floor_(o) = kFloorShare * mean_e2;
    if (!distances.empty()) {
      const auto q = distances.begin() +
                     static_cast<std::ptrdiff_t>(kReachQuantile * double(distances.size() - 1));
      std::nth_element(distances.begin(), q, distances.end());
      s.reach_(o) = *q;
    }
  }
  s.model_ = std::make_shared<const sysid::NarxModel>(model);
  return s;
}

Eigen::MatrixXd LocalSpread::At(const sysid::RegressorSpec& spec,
                                const sysid::Series& series) const {
  const sysid::RegressionData d = sysid::BuildRegression(spec, series);
  Eigen::MatrixXd sigma = Eigen::MatrixXd::Ones(d.x.rows(), d.y.cols());
  if (!model_) return sigma;
  fuzzy::Inference inf;
  for (int o = 0; o < model_->outputs(); ++o) {
    const auto& fm = model_->model(o);
    const Eigen::VectorXd& v = rule_variance_[static_cast<std::size_t>(o)];
    if (!(floor_(o) > 0.0)) continue;
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
      double var = floor_(o);
      if (fm.rules() > 0) {
        fm.rule_base().Evaluate(model_->scaling().ScaleRegressor(d.x.row(k).transpose()), &inf);
        var += inf.normalized.matrix().head(fm.rules()).dot(v);
        // Beyond the distance most training rows lie from their nearest rule, the rules know
        // nothing of the error there: the output's mean squared residual per d₉₅ farther.
        const double beyond = reach_(o) > 0.0 ? inf.min_distance / reach_(o) - 1.0 : 0.0;
        if (beyond > 0.0) var += floor_(o) / kFloorShare * std::min(beyond, 1e12);
      }
      sigma(k, o) = std::sqrt(var);
    }
  }
  return sigma;
}

}  // namespace odonata::fit

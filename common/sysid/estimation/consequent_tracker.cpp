#include "sysid/estimation/consequent_tracker.hpp"

#include "sysid/estimation/recursive_least_squares.hpp"

#include <cmath>

#include <Eigen/Cholesky>

namespace odonata::sysid {

Eigen::VectorXd ConsequentTracker::GlobalRow(const fuzzy::FuzzyModel& m,
                                             const Eigen::Ref<const Eigen::VectorXd>& x_scaled) {
  fuzzy::Inference inf;
  Eigen::VectorXd z;
  Eigen::RowVectorXd row(static_cast<Eigen::Index>(m.rules()) * m.consequent().LeastSquaresWidth());
  m.DesignRow(x_scaled, row, &inf, &z);
  return row.transpose();
}

ConsequentTracker ConsequentTracker::Build(const NarxModel& model, const Series& samples,
                                           double ridge) {
  if (samples.samples() <= model.spec().first_target()) return ConsequentTracker{};
  return Build(model, BuildRegression(model.spec(), samples), ridge);
}

ConsequentTracker ConsequentTracker::Build(const NarxModel& model, const RegressionData& d,
                                           double ridge) {
  ConsequentTracker t;
  if (d.x.rows() == 0) return t;
  for (int o = 0; o < model.outputs(); ++o) {
    const fuzzy::FuzzyModel& m = model.model(o);
    if (m.rules() == 0) return ConsequentTracker{};
    const Eigen::Index width =
        static_cast<Eigen::Index>(m.rules()) * m.consequent().LeastSquaresWidth();
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(width, width);
    for (Eigen::Index k = 0; k < d.x.rows(); ++k) {
      const Eigen::VectorXd row =
          GlobalRow(m, model.scaling().ScaleRegressor(d.x.row(k).transpose()));
      normal.selfadjointView<Eigen::Lower>().rankUpdate(row);
    }
    normal = normal.selfadjointView<Eigen::Lower>();
    normal.diagonal().array() += ridge * normal.diagonal().mean() + 1e-12;
    t.covariance_.push_back(normal.ldlt().solve(Eigen::MatrixXd::Identity(width, width)));
    if (!t.covariance_.back().allFinite()) return ConsequentTracker{};
    t.rules_.push_back(m.rules());
  }
  return t;
}

void ConsequentTracker::Step(NarxModel& model, const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  if (empty() || static_cast<int>(covariance_.size()) != model.outputs()) return;
  if (!x.allFinite() || !y.allFinite()) return;
  const Eigen::VectorXd xs = model.scaling().ScaleRegressor(x);
  for (int o = 0; o < model.outputs(); ++o) {
    fuzzy::FuzzyModel& m = model.mutable_model(o);
    if (m.rules() != rules_[static_cast<std::size_t>(o)]) return;
    Eigen::MatrixXd& p = covariance_[static_cast<std::size_t>(o)];
    const Eigen::VectorXd row = GlobalRow(m, xs);
    Eigen::MatrixXd theta = m.consequent().Parameters();
    const Eigen::VectorXd target =
        Eigen::VectorXd::Constant(1, model.scaling().ScaleOutput(o, y(o)));
    if (!RecursiveLeastSquaresStep(theta, p, row, target, m.config().forgetting)) continue;
    m.mutable_consequent().SetParameters(theta.col(0));
  }
  ++steps_;
}

}  // namespace odonata::sysid

#include "sysid/model/quadratic_arx_model.hpp"

#include <algorithm>
#include <cmath>

namespace odonata::sysid {

Eigen::VectorXd QuadraticArxModel::Features(const Eigen::VectorXd& x) const {
  const Eigen::Index products = static_cast<Eigen::Index>(lags_) * inputs_ * (inputs_ + 1) / 2;
  Eigen::VectorXd f(x.size() + products);
  f.head(x.size()) = x;
  Eigen::Index c = x.size();
  // Input i's lag l sits at first_input_ + i·lags_ + l (RegressorSpec's layout).
  for (int l = 0; l < lags_; ++l) {
    for (int i = 0; i < inputs_; ++i) {
      for (int j = i; j < inputs_; ++j) {
        f(c++) = x(first_input_ + i * lags_ + l) * x(first_input_ + j * lags_ + l);
      }
    }
  }
  return f;
}

QuadraticArxModel QuadraticArxModel::Fit(const RegressorSpec& spec, const Series& train) {
  const RegressionData d = BuildRegression(spec, train);
  QuadraticArxModel m;
  m.inputs_ = static_cast<int>(spec.inputs.size());
  m.lags_ = spec.input_lags;
  m.first_input_ = spec.output_lags * static_cast<int>(spec.outputs.size());
  const Eigen::Index n = m.Features(Eigen::VectorXd::Zero(spec.size())).size();
  // Columns scaled to unit RMS before the solve: products of raw signals span orders of
  // magnitude (f² ≈ 30 Hz², φ₀² ≈ 1 rad²), and an unscaled ridge would favour the large ones.
  Eigen::MatrixXd z(d.x.rows() + n + 1, n + 1);
  z.setZero();
  z.col(0).head(d.x.rows()).setOnes();
  for (Eigen::Index r = 0; r < d.x.rows(); ++r) {
    z.row(r).tail(n) = m.Features(d.x.row(r).transpose()).transpose();
  }
  Eigen::VectorXd scale(n + 1);
  for (Eigen::Index c = 0; c <= n; ++c) {
    const double rms = std::sqrt(z.col(c).head(d.x.rows()).squaredNorm() /
                                 static_cast<double>(std::max<Eigen::Index>(1, d.x.rows())));
    scale(c) = rms > 0.0 ? rms : 1.0;
    z.col(c).head(d.x.rows()) /= scale(c);
  }
  // The ridge as extra rows, so the QR sees it without forming normal equations.
  z.bottomRows(n + 1).diagonal().setConstant(1e-6);
  Eigen::MatrixXd y = Eigen::MatrixXd::Zero(z.rows(), d.y.cols());
  y.topRows(d.y.rows()) = d.y;
  m.theta_ = z.colPivHouseholderQr().solve(y);
  for (Eigen::Index c = 0; c <= n; ++c) m.theta_.row(c) /= scale(c);
  return m;
}

Eigen::VectorXd QuadraticArxModel::Predict(const Eigen::VectorXd& x) const {
  const Eigen::VectorXd f = Features(x);
  return theta_.bottomRows(f.size()).transpose() * f + theta_.row(0).transpose();
}

}  // namespace odonata::sysid

#include "sysid/model/arx_model.hpp"

#include <Eigen/Cholesky>

namespace odonata::sysid {

ArxModel ArxModel::Fit(const RegressorSpec& spec, const Series& train) {
  const RegressionData d = BuildRegression(spec, train);
  Eigen::MatrixXd z(d.x.rows(), d.x.cols() + 1);
  z.col(0).setOnes();
  z.rightCols(d.x.cols()) = d.x;
  Eigen::MatrixXd normal = z.transpose() * z;
  normal.diagonal().array() += 1e-10 * normal.diagonal().mean() + 1e-12;
  ArxModel m;
  m.theta_ = normal.ldlt().solve(z.transpose() * d.y);
  return m;
}

Eigen::VectorXd ArxModel::Predict(const Eigen::VectorXd& x) const {
  return theta_.transpose().rightCols(x.size()) * x + theta_.row(0).transpose();
}

}  // namespace odonata::sysid

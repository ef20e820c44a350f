#include "sysid/estimation/recursive_arx.hpp"

#include "contract/precondition.hpp"
#include "sysid/estimation/recursive_least_squares.hpp"

namespace odonata::sysid {

RecursiveArx::RecursiveArx(const Scaling& scaling, double p0) : scaling_(scaling), p0_(p0) {
  ODONATA_EXPECTS(scaling_.Problems().empty() && p0 > 0);
  Reset();
}

void RecursiveArx::Reset() {
  const Eigen::Index n = scaling_.regressor_mid.size() + 1;
  theta_ = Eigen::MatrixXd::Zero(n, scaling_.output_mean.size());
  p_ = Eigen::MatrixXd::Identity(n, n) * p0_;
  samples_ = 0;
}

Eigen::VectorXd RecursiveArx::Regressor(const Eigen::VectorXd& x) const {
  Eigen::VectorXd z(x.size() + 1);
  z(0) = 1.0;
  z.tail(x.size()) = scaling_.ScaleRegressor(x);
  return z;
}

void RecursiveArx::Update(const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  ODONATA_EXPECTS(x.size() == scaling_.regressor_mid.size() &&
                  y.size() == scaling_.output_mean.size());
  if (!x.allFinite() || !y.allFinite()) return;
  const Eigen::VectorXd z = Regressor(x);
  Eigen::VectorXd ys(y.size());
  for (Eigen::Index o = 0; o < y.size(); ++o)
    ys(o) = scaling_.ScaleOutput(static_cast<int>(o), y(o));
  RecursiveLeastSquaresStep(theta_, p_, z, ys);
  ++samples_;
}

Eigen::VectorXd RecursiveArx::Predict(const Eigen::VectorXd& x) const {
  ODONATA_EXPECTS(x.size() == scaling_.regressor_mid.size());
  const Eigen::VectorXd ys = theta_.transpose() * Regressor(x);
  Eigen::VectorXd y(ys.size());
  for (Eigen::Index o = 0; o < ys.size(); ++o)
    y(o) = scaling_.UnscaleOutput(static_cast<int>(o), ys(o));
  return y;
}

}  // namespace odonata::sysid

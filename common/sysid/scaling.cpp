#include "sysid/scaling.hpp"

#include <cmath>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::sysid {
namespace {
std::vector<double> ToVector(const Eigen::VectorXd& v) {
  return std::vector<double>(v.data(), v.data() + v.size());
}
Eigen::VectorXd FromVector(const nlohmann::json& j, const char* name) {
  const auto v = j.at(name).get<std::vector<double>>();
  for (double d : v)
    if (!std::isfinite(d))
      throw std::runtime_error(std::string("scaling.") + name + " is not finite");
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}
}  // namespace

Scaling Scaling::FromData(const Eigen::Ref<const Eigen::MatrixXd>& x,
                          const Eigen::Ref<const Eigen::MatrixXd>& y) {
  Scaling s;
  const Eigen::VectorXd lo = x.colwise().minCoeff().transpose();
  const Eigen::VectorXd hi = x.colwise().maxCoeff().transpose();
  s.regressor_mid = 0.5 * (hi + lo);
  s.regressor_half = 0.5 * (hi - lo);
  for (Eigen::Index i = 0; i < s.regressor_half.size(); ++i)
    if (!(s.regressor_half(i) > 0.0)) s.regressor_half(i) = 1.0;
  s.output_mean = y.colwise().mean().transpose();
  s.output_std.resize(y.cols());
  for (Eigen::Index o = 0; o < y.cols(); ++o) {
    const double var = (y.col(o).array() - s.output_mean(o)).square().mean();
    s.output_std(o) = var > 0.0 ? std::sqrt(var) : 1.0;
  }
  return s;
}

nlohmann::json Scaling::ToJson() const {
  return {{"regressor_mid", ToVector(regressor_mid)},
          {"regressor_half", ToVector(regressor_half)},
          {"output_mean", ToVector(output_mean)},
          {"output_std", ToVector(output_std)}};
}

Scaling Scaling::FromJson(const nlohmann::json& j) {
  Scaling s;
  s.regressor_mid = FromVector(j, "regressor_mid");
  s.regressor_half = FromVector(j, "regressor_half");
  s.output_mean = FromVector(j, "output_mean");
  s.output_std = FromVector(j, "output_std");
  if (s.regressor_mid.size() != s.regressor_half.size() ||
      s.output_mean.size() != s.output_std.size()) {
    throw std::runtime_error("scaling: vector sizes differ");
  }
  if ((s.regressor_half.array() <= 0).any() || (s.output_std.array() <= 0).any()) {
    throw std::runtime_error("scaling: a range or standard deviation is not positive");
  }
  return s;
}

}  // namespace odonata::sysid

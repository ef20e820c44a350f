#include "sysid/model/scaling.hpp"

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

std::string Scaling::Problems() const {
  if (regressor_mid.size() != regressor_half.size() || output_mean.size() != output_std.size()) {
    return "scaling: vector sizes differ";
  }
  if (!regressor_mid.allFinite() || !output_mean.allFinite()) {
    return "scaling: a centre or mean is not finite";
  }
  const auto positive = [](const Eigen::VectorXd& v) {
    return v.allFinite() && (v.array() > 0).all();
  };
  if (!positive(regressor_half) || !positive(output_std)) {
    return "scaling: a range or standard deviation is not positive";
  }
  // Finite but absurd: beyond 1e200 a scaled value overflows on the way, and a range below the
  // resolution of its own centre scales every input to noise.
  const auto sane = [](const Eigen::VectorXd& centre, const Eigen::VectorXd& half) {
    for (Eigen::Index i = 0; i < centre.size(); ++i)
      if (!(std::abs(centre(i)) <= kMaxMagnitude && half(i) <= kMaxMagnitude &&
            half(i) >= kMinMagnitude && half(i) >= 1e-12 * std::abs(centre(i))))
        return false;
    return true;
  };
  if (!sane(regressor_mid, regressor_half) || !sane(output_mean, output_std))
    return "scaling: a centre, range or standard deviation beyond 1e200, below 1e-200, or below "
           "1e-12 of its centre";
  return "";
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
  const std::string problems = s.Problems();
  if (!problems.empty()) throw std::runtime_error(problems);
  return s;
}

}  // namespace odonata::sysid

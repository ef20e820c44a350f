#include "sysid/model/data_envelope.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "fuzzy/fuzzy_model.hpp"

namespace odonata::sysid {

DataEnvelope DataEnvelope::Fit(const std::vector<fuzzy::FuzzyModel>& models,
                               const Eigen::Ref<const Eigen::MatrixXd>& xs,
                               const Eigen::Ref<const Eigen::MatrixXd>& ys) {
  DataEnvelope e;
  const bool fuzzy = std::any_of(models.begin(), models.end(),
                                 [](const fuzzy::FuzzyModel& m) { return m.rules() > 1; });
  const Eigen::Index rows = xs.rows(), n = xs.cols() + 1;
  if (!fuzzy || rows < n) return e;
  Eigen::MatrixXd a(rows, n);
  a.col(0).setOnes();
  a.rightCols(xs.cols()) = xs;
  // The same tiny relative ridge as the consequents' solve (TrainOptions::ridge), so a constant
  // regressor does not make it singular.
  const Eigen::MatrixXd ata = a.transpose() * a;
  const double ridge = 1e-10 * ata.diagonal().mean();
  const Eigen::LDLT<Eigen::MatrixXd> solve(ata + ridge * Eigen::MatrixXd::Identity(n, n));
  e.lower = xs.colwise().minCoeff().transpose();
  e.upper = xs.colwise().maxCoeff().transpose();
  for (std::size_t o = 0; o < models.size(); ++o) {
    OutputEnvelope out;
    out.linear = solve.solve(a.transpose() * ys.col(static_cast<Eigen::Index>(o)));
    for (Eigen::Index r = 0; r < rows; ++r)
      out.radius_widths =
          std::max(out.radius_widths, models[o].NearestRuleDistance(xs.row(r).transpose()));
    if (!out.linear.allFinite() || !std::isfinite(out.radius_widths)) return DataEnvelope{};
    e.outputs.push_back(std::move(out));
  }
  return e;
}

namespace {

// 0 at or below 0, 1 from 1 on, smoothstep between: the prediction's slope stays continuous. A
// NaN is 0 (Blend keeps the fuzzy NaN).
double Smoothstep(double t) {
  if (!(t > 0.0)) return 0.0;
  if (t >= 1.0) return 1.0;
  return t * t * (3.0 - 2.0 * t);
}

}  // namespace

double DataEnvelope::LinearShare(int output, const Eigen::Ref<const Eigen::VectorXd>& x,
                                 double distance_widths) const {
  if (outputs.empty()) return 0.0;
  double beyond = 0.0;  // the farthest a regressor lies outside the box, in shares of its span
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double span = std::max(upper(i) - lower(i), 1e-12);
    beyond = std::max(beyond, std::max(lower(i) - x(i), x(i) - upper(i)) / span);
  }
  const double by_rules =
      (distance_widths - outputs[static_cast<std::size_t>(output)].radius_widths) / kBlendWidths;
  return std::max(Smoothstep(by_rules), Smoothstep(beyond / kBoxBlendSpan));
}

double DataEnvelope::Blend(int output, const Eigen::Ref<const Eigen::VectorXd>& x, double fuzzy,
                           double share) const {
  if (share == 0.0) return fuzzy;
  const Eigen::VectorXd& th = outputs[static_cast<std::size_t>(output)].linear;
  const double linear = th(0) + th.tail(th.size() - 1).dot(x);
  if (share == 1.0) return linear;
  return (1.0 - share) * fuzzy + share * linear;
}

std::string DataEnvelope::Problems(int n_outputs, int regressors) const {
  if (outputs.empty()) return "";
  std::ostringstream p;
  if (lower.size() != regressors || upper.size() != regressors)
    p << "data_envelope: the box has " << lower.size() << " lower and " << upper.size()
      << " upper bounds, for a regressor of " << regressors << "\n";
  else if (!lower.allFinite() || !upper.allFinite() || (lower.array() > upper.array()).any())
    p << "data_envelope: a box bound is not finite, or a lower one is above its upper one\n";
  if (static_cast<int>(outputs.size()) != n_outputs)
    p << "data_envelope: " << outputs.size() << " outputs, the model has " << n_outputs << "\n";
  for (std::size_t o = 0; o < outputs.size(); ++o) {
    const OutputEnvelope& e = outputs[o];
    if (e.linear.size() != regressors + 1)
      p << "data_envelope[" << o << "].linear: " << e.linear.size() << " coefficients, expected "
        << regressors + 1 << " (intercept and one per regressor)\n";
    else if (!e.linear.allFinite())
      p << "data_envelope[" << o << "].linear: a coefficient is not finite\n";
    if (!(std::isfinite(e.radius_widths) && e.radius_widths >= 0.0))
      p << "data_envelope[" << o << "].radius_widths: must be finite and >= 0\n";
  }
  std::string s = p.str();
  if (!s.empty()) s.pop_back();
  return s;
}

namespace {

std::vector<double> Values(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXd Vector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

}  // namespace

nlohmann::json DataEnvelope::ToJson() const {
  nlohmann::json per_output = nlohmann::json::array();
  for (const OutputEnvelope& e : outputs)
    per_output.push_back({{"linear", Values(e.linear)}, {"radius_widths", e.radius_widths}});
  return {{"lower", Values(lower)}, {"upper", Values(upper)}, {"outputs", per_output}};
}

DataEnvelope DataEnvelope::FromJson(const nlohmann::json& j) {
  DataEnvelope e;
  e.lower = Vector(j.at("lower").get<std::vector<double>>());
  e.upper = Vector(j.at("upper").get<std::vector<double>>());
  const auto& per_output = j.at("outputs");
  if (!per_output.is_array())
    throw std::runtime_error("data_envelope.outputs: expected an array, one per output");
  for (const auto& o : per_output) {
    OutputEnvelope out;
    out.linear = Vector(o.at("linear").get<std::vector<double>>());
    out.radius_widths = o.at("radius_widths").get<double>();
    e.outputs.push_back(std::move(out));
  }
  return e;
}

}  // namespace odonata::sysid

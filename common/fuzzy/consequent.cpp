#include "fuzzy/consequent.hpp"

#include "fuzzy/fuzzy_model_state.hpp"

#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <string>

#include "fuzzy/linear_consequent.hpp"
#include "fuzzy/singleton_consequent.hpp"

namespace odonata::fuzzy {
namespace {
// Defaults for the online consequent learners; see the classes for the update rules.
constexpr double kNlmsRate = 0.5;
constexpr double kNlmsRegulariser = 1e-3;
constexpr double kRlsInitialCovariance = 1e3;
}  // namespace

const char* ToString(ConsequentKind kind) {
  return kind == ConsequentKind::kSingleton ? "singleton" : "linear";
}

ConsequentKind ConsequentKindFromString(const std::string& name) {
  if (name == "singleton") return ConsequentKind::kSingleton;
  if (name == "linear") return ConsequentKind::kLinear;
  throw std::invalid_argument("unknown consequent '" + name + "' (expected singleton or linear)");
}

std::unique_ptr<Consequent> MakeConsequent(ConsequentKind kind, int inputs, int capacity,
                                           double forgetting) {
  if (kind == ConsequentKind::kSingleton) {
    return std::make_unique<SingletonConsequent>(capacity, kNlmsRate, kNlmsRegulariser);
  }
  return std::make_unique<LinearConsequent>(inputs, capacity, kRlsInitialCovariance, forgetting);
}

namespace {
bool Finite(const std::vector<double>& v) {
  for (double x : v)
    if (!std::isfinite(x)) return false;
  return true;
}
// Finite and within ±bound: a model whose numbers pass these stays finite on inputs of its range.
bool Within(const std::vector<double>& v, double bound) {
  for (double x : v)
    if (!(std::abs(x) <= bound)) return false;
  return true;
}
std::string Number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%g", v);
  return b;
}
}  // namespace

std::unique_ptr<Consequent> ConsequentFromState(const ConsequentState& s, int inputs,
                                                int capacity) {
  if (static_cast<int>(s.coefficients.size()) > capacity) {
    throw std::runtime_error("more consequents than the rule capacity");
  }
  if (s.kind == ConsequentKind::kSingleton) {
    if (!(s.rate >= 0 && s.rate <= kMaxLearnerSetting) ||
        !(s.regulariser >= 0 && s.regulariser <= kMaxLearnerSetting))
      throw std::runtime_error("singleton consequent: rate " + Number(s.rate) + " or regulariser " +
                               Number(s.regulariser) + " is not in [0, " +
                               Number(kMaxLearnerSetting) + "]");
    auto c = std::make_unique<SingletonConsequent>(capacity, s.rate, s.regulariser);
    const Eigen::ArrayXd none;
    for (const auto& b : s.coefficients) {
      if (b.size() != 1)
        throw std::runtime_error("singleton consequent: a rule has several centres");
      if (!Within(b, kMaxCoefficient))
        throw std::runtime_error("singleton consequent: a centre is not finite or beyond ±" +
                                 Number(kMaxCoefficient) + " (scaled units)");
      c->AddRule(Eigen::VectorXd::Zero(inputs), b[0], none);
    }
    return c;
  }
  // A forgetting factor of 0 divides by zero at the first update; a covariance of 1e300 overflows
  // it: both gave NaN predictions from the fourth sample on.
  if (!(s.forgetting > 0 && s.forgetting <= 1))
    throw std::runtime_error("linear consequent: forgetting " + Number(s.forgetting) +
                             " is not in (0, 1]");
  if (!(s.initial_covariance > 0 && s.initial_covariance <= kMaxCovariance))
    throw std::runtime_error("linear consequent: initial_covariance " +
                             Number(s.initial_covariance) + " is not in (0, " +
                             Number(kMaxCovariance) + "]");
  auto c = std::make_unique<LinearConsequent>(inputs, capacity, s.initial_covariance, s.forgetting);
  if (s.coefficients.size() != s.covariances.size()) {
    throw std::runtime_error("linear consequent: coefficient and covariance counts differ");
  }
  const int n1 = inputs + 1;
  for (std::size_t r = 0; r < s.coefficients.size(); ++r) {
    const auto& coef = s.coefficients[r];
    const auto& cov = s.covariances[r];
    if (static_cast<int>(coef.size()) != n1 || static_cast<int>(cov.size()) != n1 * n1) {
      throw std::runtime_error("linear consequent: rule " + std::to_string(r + 1) +
                               " has the wrong number of coefficients");
    }
    if (!Finite(coef) || !Finite(cov)) {
      throw std::runtime_error("linear consequent: rule " + std::to_string(r + 1) +
                               " has a value that is not finite");
    }
    if (!Within(coef, kMaxCoefficient))
      throw std::runtime_error("linear consequent: rule " + std::to_string(r + 1) +
                               " has a coefficient beyond ±" + Number(kMaxCoefficient) +
                               " (scaled units)");
    if (!Within(cov, kMaxCovariance))
      throw std::runtime_error("linear consequent: rule " + std::to_string(r + 1) +
                               " has a covariance entry beyond ±" + Number(kMaxCovariance));
    c->theta_.col(static_cast<Eigen::Index>(r)) =
        Eigen::Map<const Eigen::VectorXd>(coef.data(), n1);
    c->covariances_.push_back(Eigen::Map<const Eigen::MatrixXd>(cov.data(), n1, n1));
    ++c->rules_;
  }
  return c;
}

}  // namespace odonata::fuzzy

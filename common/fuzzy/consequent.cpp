#include "fuzzy/consequent.hpp"

#include <stdexcept>

#include <nlohmann/json.hpp>

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

std::unique_ptr<Consequent> ConsequentFromJson(const nlohmann::json& j, int inputs, int capacity) {
  const ConsequentKind kind = ConsequentKindFromString(j.at("kind").get<std::string>());
  if (kind == ConsequentKind::kSingleton) {
    auto c = std::make_unique<SingletonConsequent>(capacity, j.at("rate").get<double>(),
                                                   j.at("regulariser").get<double>());
    const auto centres = j.at("centres").get<std::vector<double>>();
    if (static_cast<int>(centres.size()) > capacity) {
      throw std::runtime_error("more consequents than the rule capacity");
    }
    const Eigen::ArrayXd none;
    for (double b : centres) c->AddRule(Eigen::VectorXd::Zero(inputs), b, none);
    return c;
  }
  auto c = std::make_unique<LinearConsequent>(
      inputs, capacity, j.at("initial_covariance").get<double>(), j.at("forgetting").get<double>());
  const auto coef = j.at("coefficients").get<std::vector<std::vector<double>>>();
  const auto cov = j.at("covariances").get<std::vector<std::vector<double>>>();
  if (coef.size() != cov.size() || static_cast<int>(coef.size()) > capacity) {
    throw std::runtime_error("linear consequent: coefficient and covariance counts differ");
  }
  const int n1 = inputs + 1;
  for (std::size_t r = 0; r < coef.size(); ++r) {
    if (static_cast<int>(coef[r].size()) != n1 || static_cast<int>(cov[r].size()) != n1 * n1) {
      throw std::runtime_error("linear consequent: rule " + std::to_string(r + 1) +
                               " has the wrong number of coefficients");
    }
    c->theta_.col(static_cast<Eigen::Index>(r)) =
        Eigen::Map<const Eigen::VectorXd>(coef[r].data(), n1);
    c->covariances_.push_back(Eigen::Map<const Eigen::MatrixXd>(cov[r].data(), n1, n1));
    ++c->rules_;
  }
  return c;
}

}  // namespace odonata::fuzzy

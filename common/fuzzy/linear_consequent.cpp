#include "fuzzy/linear_consequent.hpp"

#include <cassert>

#include <nlohmann/json.hpp>

namespace odonata::fuzzy {

LinearConsequent::LinearConsequent(int inputs, int capacity, double initial_covariance,
                                   double forgetting)
    : inputs_(inputs),
      initial_covariance_(initial_covariance),
      forgetting_(forgetting),
      theta_(Eigen::MatrixXd::Zero(inputs + 1, capacity)),
      z_(inputs + 1),
      pz_(inputs + 1) {
  covariances_.reserve(static_cast<std::size_t>(capacity));
}

std::unique_ptr<Consequent> LinearConsequent::Clone() const {
  return std::make_unique<LinearConsequent>(*this);
}

void LinearConsequent::RuleOutputs(const Eigen::Ref<const Eigen::VectorXd>& x, int rules,
                                   Eigen::ArrayXd* out) const {
  // y_j = a_j0 + Σ_i a_ji x_i for all rules at once.
  out->resize(rules);
  out->matrix().noalias() = theta_.leftCols(rules).bottomRows(inputs_).transpose() * x;
  *out += theta_.row(0).head(rules).transpose().array();
}

void LinearConsequent::AddRule(const Eigen::Ref<const Eigen::VectorXd>& x, double target,
                               const Eigen::Ref<const Eigen::ArrayXd>& phi_existing) {
  assert(rules_ < theta_.cols());
  Eigen::VectorXd theta = Eigen::VectorXd::Zero(inputs_ + 1);
  if (rules_ > 0) {
    // Inherit the local slope of the neighbourhood, then move the intercept so the new rule
    // reproduces the sample that created it: the slope is the smoothest guess, the target exact.
    theta = theta_.leftCols(rules_) * phi_existing.matrix();
  }
  theta(0) = target - theta.tail(inputs_).dot(x);
  theta_.col(rules_) = theta;
  covariances_.push_back(initial_covariance_ * Eigen::MatrixXd::Identity(inputs_ + 1, inputs_ + 1));
  ++rules_;
}

void LinearConsequent::RemoveRule(int rule) {
  assert(rule >= 0 && rule < rules_);
  const int tail = rules_ - rule - 1;
  if (tail > 0) theta_.middleCols(rule, tail) = theta_.middleCols(rule + 1, tail).eval();
  covariances_.erase(covariances_.begin() + rule);
  --rules_;
}

void LinearConsequent::Update(const Eigen::Ref<const Eigen::VectorXd>& x,
                              const Eigen::Ref<const Eigen::ArrayXd>& phi, double, double target) {
  z_(0) = 1.0;
  z_.tail(inputs_) = x;
  for (int j = 0; j < rules_; ++j) {
    const double w = phi(j);
    if (w < kActiveFiring) continue;
    auto& p = covariances_[static_cast<std::size_t>(j)];
    pz_.noalias() = p.selfadjointView<Eigen::Lower>() * z_;
    const double denom = 1.0 + w * z_.dot(pz_);
    const double local_error = target - theta_.col(j).dot(z_);
    theta_.col(j) += (w * local_error / denom) * pz_;
    p.selfadjointView<Eigen::Lower>().rankUpdate(pz_, -w / denom);
    if (forgetting_ < 1.0) {
      // Forgetting raises P; keep its trace at most the initial one so a long quiet spell cannot
      // blow it up (a wound-up P turns the next sample into a violent step).
      p.triangularView<Eigen::Lower>() /= 1.0 - w * (1.0 - forgetting_);
      const double cap = initial_covariance_ * (inputs_ + 1);
      const double trace = p.diagonal().sum();
      if (trace > cap) p.triangularView<Eigen::Lower>() *= cap / trace;
    }
  }
}

Eigen::VectorXd LinearConsequent::Gradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                                           const Eigen::Ref<const Eigen::ArrayXd>& phi,
                                           double error) const {
  Eigen::VectorXd g(rules_ * (inputs_ + 1));
  for (int j = 0; j < rules_; ++j) {
    g(j * (inputs_ + 1)) = error * phi(j);
    g.segment(j * (inputs_ + 1) + 1, inputs_) = error * phi(j) * x;
  }
  return g;
}

Eigen::VectorXd LinearConsequent::Parameters() const {
  Eigen::VectorXd p(rules_ * (inputs_ + 1));
  for (int j = 0; j < rules_; ++j) p.segment(j * (inputs_ + 1), inputs_ + 1) = theta_.col(j);
  return p;
}

void LinearConsequent::SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) {
  assert(p.size() == rules_ * (inputs_ + 1));
  for (int j = 0; j < rules_; ++j) theta_.col(j) = p.segment(j * (inputs_ + 1), inputs_ + 1);
}

void LinearConsequent::LeastSquaresRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                                       Eigen::Ref<Eigen::VectorXd> z) const {
  z(0) = 1.0;
  z.tail(inputs_) = x;
}

void LinearConsequent::SetFromLeastSquares(const Eigen::Ref<const Eigen::VectorXd>& theta) {
  SetParameters(theta);
}

nlohmann::json LinearConsequent::ToJson() const {
  nlohmann::json j;
  j["kind"] = ToString(kind());
  j["initial_covariance"] = initial_covariance_;
  j["forgetting"] = forgetting_;
  nlohmann::json coef = nlohmann::json::array();
  nlohmann::json cov = nlohmann::json::array();
  for (int r = 0; r < rules_; ++r) {
    const Eigen::VectorXd c = theta_.col(r);
    coef.push_back(std::vector<double>(c.data(), c.data() + c.size()));
    // Only the lower triangle is maintained by the rank update; store the full symmetric matrix
    // so a reloaded model resumes learning exactly where it stopped.
    const auto& p = covariances_[static_cast<std::size_t>(r)];
    const Eigen::MatrixXd full = p.selfadjointView<Eigen::Lower>();
    cov.push_back(std::vector<double>(full.data(), full.data() + full.size()));
  }
  j["coefficients"] = coef;
  j["covariances"] = cov;
  return j;
}

}  // namespace odonata::fuzzy

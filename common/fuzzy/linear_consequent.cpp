#include "fuzzy/linear_consequent.hpp"

#include "fuzzy/fuzzy_model_state.hpp"

#include "contract/precondition.hpp"

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
  // y_j = a_j0 + Σ_i a_ji x_i. Column j of θ is contiguous, so a short dot product per rule
  // beats a strided matrix–vector product at these sizes.
  out->resize(rules);
  const int n1 = inputs_ + 1;
  const double* xs = x.data();
  for (int j = 0; j < rules; ++j) {
    const double* t = theta_.data() + static_cast<Eigen::Index>(j) * n1;
    double y = t[0];
    for (int i = 0; i < inputs_; ++i) y += t[i + 1] * xs[i];
    (*out)(j) = y;
  }
}

void LinearConsequent::AddRule(const Eigen::Ref<const Eigen::VectorXd>& x, double target,
                               const Eigen::Ref<const Eigen::ArrayXd>& phi_existing) {
  ODONATA_EXPECTS(rules_ < theta_.cols());
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
  ODONATA_EXPECTS(rule >= 0 && rule < rules_);
  const int tail = rules_ - rule - 1;
  if (tail > 0) theta_.middleCols(rule, tail) = theta_.middleCols(rule + 1, tail).eval();
  covariances_.erase(covariances_.begin() + rule);
  --rules_;
}

void LinearConsequent::Update(const Eigen::Ref<const Eigen::VectorXd>& x,
                              const Eigen::Ref<const Eigen::ArrayXd>& phi, double, double target) {
  z_(0) = 1.0;
  z_.tail(inputs_) = x;
  const int n1 = inputs_ + 1;
  for (int j = 0; j < rules_; ++j) {
    const double w = phi(j);
    if (w < kActiveFiring) continue;
    // P is kept full (symmetric by construction). At (N+1)² ≈ 50 entries, plain loops over raw
    // storage beat Eigen's dynamic-size expressions, whose per-call overhead dominates here.
    double* p = covariances_[static_cast<std::size_t>(j)].data();
    double* theta = theta_.col(j).data();
    double* pz = pz_.data();
    const double* z = z_.data();
    double zpz = 0.0, prediction = 0.0;
    for (int a = 0; a < n1; ++a) pz[a] = 0.0;
    for (int b = 0; b < n1; ++b) {
      const double zb = z[b];
      const double* col = p + b * n1;
      for (int a = 0; a < n1; ++a) pz[a] += col[a] * zb;
      prediction += theta[b] * zb;
    }
    for (int a = 0; a < n1; ++a) zpz += z[a] * pz[a];
    const double denom = 1.0 + w * zpz;
    const double gain = w * (target - prediction) / denom;
    for (int a = 0; a < n1; ++a) theta[a] += gain * pz[a];
    const double k = w / denom;
    // Forgetting raises P by 1/λ_j; a trace cap keeps a long quiet spell from winding it up (a
    // wound-up P turns the next sample into a violent step).
    const double inflate = forgetting_ < 1.0 ? 1.0 / (1.0 - w * (1.0 - forgetting_)) : 1.0;
    // P must stay exactly symmetric: forgetting would amplify any skew part step after step until
    // the update diverges. (pz_a · pz_b) · k is the same floating-point number for (a, b) and
    // (b, a), since multiplication commutes exactly, so full columns can be updated (and
    // vectorised) without mirroring.
    double trace = 0.0;
    for (int b = 0; b < n1; ++b) {
      double* col = p + b * n1;
      const double pzb = pz[b];
      for (int a = 0; a < n1; ++a) col[a] = (col[a] - (pz[a] * pzb) * k) * inflate;
      trace += col[b];
    }
    if (forgetting_ < 1.0) {
      const double cap = initial_covariance_ * n1;
      if (trace > cap)
        for (int e = 0; e < n1 * n1; ++e) p[e] *= cap / trace;
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

void LinearConsequent::AddInputGradient(const Eigen::Ref<const Eigen::ArrayXd>& phi,
                                        Eigen::Ref<Eigen::VectorXd> dydx) const {
  for (int j = 0; j < rules_; ++j) dydx += phi(j) * theta_.col(j).tail(inputs_);
}

Eigen::VectorXd LinearConsequent::Parameters() const {
  Eigen::VectorXd p(rules_ * (inputs_ + 1));
  for (int j = 0; j < rules_; ++j) p.segment(j * (inputs_ + 1), inputs_ + 1) = theta_.col(j);
  return p;
}

void LinearConsequent::SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) {
  ODONATA_EXPECTS(p.size() == rules_ * (inputs_ + 1));
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

ConsequentState LinearConsequent::State() const {
  ConsequentState s;
  s.kind = kind();
  s.initial_covariance = initial_covariance_;
  s.forgetting = forgetting_;
  for (int r = 0; r < rules_; ++r) {
    const Eigen::VectorXd c = theta_.col(r);
    s.coefficients.emplace_back(c.data(), c.data() + c.size());
    const auto& p = covariances_[static_cast<std::size_t>(r)];
    s.covariances.emplace_back(p.data(), p.data() + p.size());
  }
  return s;
}

}  // namespace odonata::fuzzy

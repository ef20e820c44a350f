#include "fuzzy/singleton_consequent.hpp"

#include "fuzzy/fuzzy_model_state.hpp"

#include "contract/precondition.hpp"

namespace odonata::fuzzy {

SingletonConsequent::SingletonConsequent(int capacity, double rate, double regulariser)
    : rate_(rate), regulariser_(regulariser), centres_(Eigen::ArrayXd::Zero(capacity)) {}

std::unique_ptr<Consequent> SingletonConsequent::Clone() const {
  return std::make_unique<SingletonConsequent>(*this);
}

void SingletonConsequent::RuleOutputs(const Eigen::Ref<const Eigen::VectorXd>&, int rules,
                                      Eigen::ArrayXd* out) const {
  *out = centres_.head(rules);
}

void SingletonConsequent::AddRule(const Eigen::Ref<const Eigen::VectorXd>&, double target,
                                  const Eigen::Ref<const Eigen::ArrayXd>&) {
  ODONATA_EXPECTS(rules_ < centres_.size());
  centres_(rules_++) = target;
}

void SingletonConsequent::RemoveRule(int rule) {
  ODONATA_EXPECTS(rule >= 0 && rule < rules_);
  const int tail = rules_ - rule - 1;
  if (tail > 0) centres_.segment(rule, tail) = centres_.segment(rule + 1, tail).eval();
  --rules_;
}

void SingletonConsequent::Update(const Eigen::Ref<const Eigen::VectorXd>&,
                                 const Eigen::Ref<const Eigen::ArrayXd>& phi, double error,
                                 double) {
  const double step = rate_ * error / (regulariser_ + phi.square().sum());
  centres_.head(rules_) -= step * phi;
}

Eigen::VectorXd SingletonConsequent::Gradient(const Eigen::Ref<const Eigen::VectorXd>&,
                                              const Eigen::Ref<const Eigen::ArrayXd>& phi,
                                              double error) const {
  return (error * phi).matrix();
}

void SingletonConsequent::SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) {
  ODONATA_EXPECTS(p.size() == rules_);
  centres_.head(rules_) = p.array();
}

void SingletonConsequent::LeastSquaresRow(const Eigen::Ref<const Eigen::VectorXd>&,
                                          Eigen::Ref<Eigen::VectorXd> z) const {
  z(0) = 1.0;
}

void SingletonConsequent::SetFromLeastSquares(const Eigen::Ref<const Eigen::VectorXd>& theta) {
  SetParameters(theta);
}

ConsequentState SingletonConsequent::State() const {
  ConsequentState s;
  s.kind = kind();
  s.rate = rate_;
  s.regulariser = regulariser_;
  for (int r = 0; r < rules_; ++r) s.coefficients.push_back({centres_(r)});
  return s;
}

}  // namespace odonata::fuzzy

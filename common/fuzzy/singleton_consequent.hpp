#pragma once

#include "fuzzy/consequent.hpp"

namespace odonata::fuzzy {

/// The paper's consequents: one output centre b_j per rule. Learns by normalised LMS,
/// b ← b − η e φ / (δ + ‖φ‖²), which is stable for 0 < η < 2 whatever the rule count
/// (the plain gradient e φ_j of docs/identifier.md §3 with a step normalised by ‖φ‖²).
class SingletonConsequent final : public Consequent {
 public:
  SingletonConsequent(int capacity, double rate, double regulariser);

  ConsequentKind kind() const override { return ConsequentKind::kSingleton; }
  std::unique_ptr<Consequent> Clone() const override;
  void RuleOutputs(const Eigen::Ref<const Eigen::VectorXd>& x, int rules,
                   Eigen::ArrayXd* out) const override;
  void AddRule(const Eigen::Ref<const Eigen::VectorXd>& x, double target,
               const Eigen::Ref<const Eigen::ArrayXd>& phi_existing) override;
  void RemoveRule(int rule) override;
  void Update(const Eigen::Ref<const Eigen::VectorXd>& x,
              const Eigen::Ref<const Eigen::ArrayXd>& phi, double error, double target) override;
  /// Singletons do not depend on x.
  void AddInputGradient(const Eigen::Ref<const Eigen::ArrayXd>& /*phi*/,
                        Eigen::Ref<Eigen::VectorXd> /*dydx*/) const override {}
  Eigen::VectorXd Gradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                           const Eigen::Ref<const Eigen::ArrayXd>& phi,
                           double error) const override;
  Eigen::VectorXd Parameters() const override { return centres_.head(rules_).matrix(); }
  void SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) override;
  int LeastSquaresWidth() const override { return 1; }
  void LeastSquaresRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                       Eigen::Ref<Eigen::VectorXd> z) const override;
  void SetFromLeastSquares(const Eigen::Ref<const Eigen::VectorXd>& theta) override;
  int rules() const override { return rules_; }
  ConsequentState State() const override;

  double centre(int rule) const { return centres_(rule); }

 private:
  int rules_ = 0;
  double rate_;         // η
  double regulariser_;  // δ
  Eigen::ArrayXd centres_;
};

}  // namespace odonata::fuzzy

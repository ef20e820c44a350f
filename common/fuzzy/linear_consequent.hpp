#pragma once

#include <vector>

#include "fuzzy/consequent.hpp"

namespace odonata::fuzzy {

/// First-order Takagi–Sugeno consequents y_j = θ_jᵀ z, z = [1, x]. Learns online by local
/// φ-weighted recursive least squares per rule (eTS, docs/identifier.md §2):
///   P_j ← (P_j − φ_j P_j z zᵀ P_j / (1 + φ_j zᵀ P_j z)) / λ_j,  θ_j ← θ_j + φ_j P_j z (y − zᵀθ_j),
/// with λ_j = 1 − φ_j (1 − λ): a rule forgets in proportion to how much it fires, so a rule the
/// data no longer visits keeps its covariance instead of winding it up. Only rules whose
/// normalised firing reaches kActiveFiring learn: the others would move by less than rounding.
/// Local (per-rule) rather than global RLS keeps each rule interpretable as a local linear model
/// and the cost at O(R N²).
class LinearConsequent final : public Consequent {
 public:
  /// @param initial_covariance Ω in P = Ω I for a new rule.
  /// @param forgetting λ ∈ (0, 1]; 1 never forgets.
  LinearConsequent(int inputs, int capacity, double initial_covariance, double forgetting);

  ConsequentKind kind() const override { return ConsequentKind::kLinear; }
  std::unique_ptr<Consequent> Clone() const override;
  void RuleOutputs(const Eigen::Ref<const Eigen::VectorXd>& x, int rules,
                   Eigen::ArrayXd* out) const override;
  void AddRule(const Eigen::Ref<const Eigen::VectorXd>& x, double target,
               const Eigen::Ref<const Eigen::ArrayXd>& phi_existing) override;
  void RemoveRule(int rule) override;
  void SetForgetting(double lambda) override { forgetting_ = lambda; }
  void Update(const Eigen::Ref<const Eigen::VectorXd>& x,
              const Eigen::Ref<const Eigen::ArrayXd>& phi, double error, double target) override;
  void AddInputGradient(const Eigen::Ref<const Eigen::ArrayXd>& phi,
                        Eigen::Ref<Eigen::VectorXd> dydx) const override;
  Eigen::VectorXd Gradient(const Eigen::Ref<const Eigen::VectorXd>& x,
                           const Eigen::Ref<const Eigen::ArrayXd>& phi,
                           double error) const override;
  Eigen::VectorXd Parameters() const override;
  void SetParameters(const Eigen::Ref<const Eigen::VectorXd>& p) override;
  int LeastSquaresWidth() const override { return inputs_ + 1; }
  void LeastSquaresRow(const Eigen::Ref<const Eigen::VectorXd>& x,
                       Eigen::Ref<Eigen::VectorXd> z) const override;
  void SetFromLeastSquares(const Eigen::Ref<const Eigen::VectorXd>& theta) override;
  int rules() const override { return rules_; }
  ConsequentState State() const override;

  /// Rules with a smaller normalised firing skip the RLS step (most of its O(R N²) cost).
  static constexpr double kActiveFiring = 1e-2;
  double forgetting() const { return forgetting_; }

  /// θ_j = [a_j0, a_j1 … a_jN] in scaled units.
  Eigen::VectorXd coefficients(int rule) const { return theta_.col(rule); }

 private:
  friend std::unique_ptr<Consequent> ConsequentFromState(const ConsequentState&, int, int);
  int inputs_;
  int rules_ = 0;
  double initial_covariance_;
  double forgetting_;
  Eigen::MatrixXd theta_;                     // (N+1) × capacity, one column per rule
  std::vector<Eigen::MatrixXd> covariances_;  // P_j, (N+1)²
  Eigen::VectorXd z_;                         // scratch [1, x]
  Eigen::VectorXd pz_;                        // scratch P z
};

}  // namespace odonata::fuzzy

#pragma once
// Antecedents of the fuzzy network: layers 2–4 of the paper (docs/identifier.md §1).

#include <Eigen/Core>

namespace odonata::fuzzy {

/// Regularises every variance and output width so no division is ever by zero.
inline constexpr double kEpsilon = 1e-6;

/// Per-sample inference state, reused across calls so the hot path never allocates.
struct Inference {
  Eigen::ArrayXd weighted_distance;  ///< d_j = Σ_i (x_i − c_ji)² / (σ_ji² + ε), per rule.
  Eigen::ArrayXd normalized;         ///< φ_j = w_j / Σ_k w_k, per rule (layer 5 weights).
  double min_distance = 0.0;         ///< min_j d_j (the nearest rule in the Mahalanobis sense).
  double max_firing = 0.0;           ///< max_j F_j = exp(−½ min_j d_j).
  int nearest_rule = -1;             ///< argmin_j d_j, or −1 when there is no rule.
};

/// Gaussian rule antecedents, stored rule-major per input (column i holds c_·i for all rules) so
/// the per-rule sums vectorise. Storage is reserved for `capacity` rules up front: growing a rule
/// never reallocates, which keeps online steps allocation-free and bounds memory.
class GaussianRuleBase {
 public:
  GaussianRuleBase() = default;
  /// @pre inputs ≥ 1, capacity ≥ 1.
  GaussianRuleBase(int inputs, int capacity);

  int inputs() const { return inputs_; }
  int rules() const { return rules_; }
  int capacity() const { return capacity_; }

  /// Appends a rule with centre `centre`, widths `sigma` and output width s = 1.
  /// @pre rules() < capacity(); sizes equal inputs().
  void AddRule(const Eigen::Ref<const Eigen::VectorXd>& centre,
               const Eigen::Ref<const Eigen::VectorXd>& sigma, double output_width = 1.0);

  /// Layers 2–5 weights for input x. The firing strengths are computed as one exp of a shifted
  /// sum (log-sum-exp): φ is unchanged by the shift, and it never underflows to 0/0 far from
  /// every rule. Resizes `out` only when the rule count changed.
  void Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x, Inference* out) const;

  /// Removes rule `rule`; later rules move up one place (their order is kept, so learning stays
  /// deterministic). @pre 0 ≤ rule < rules().
  void RemoveRule(int rule);

  double centre(int rule, int input) const { return centres_(rule, input); }
  double sigma(int rule, int input) const { return sigmas_(rule, input); }
  double output_width(int rule) const { return output_widths_(rule); }
  void set_centre(int rule, int input, double v) { centres_(rule, input) = v; }
  void set_sigma(int rule, int input, double v);
  void set_output_width(int rule, double v);

  /// Column i (input i) over the active rules.
  auto centres_of_input(int i) const { return centres_.col(i).head(rules_); }
  auto sigmas_of_input(int i) const { return sigmas_.col(i).head(rules_); }
  auto inverse_variances_of_input(int i) const { return inverse_variances_.col(i).head(rules_); }
  auto output_widths() const { return output_widths_.head(rules_); }
  auto inverse_output_weights() const { return inverse_output_weights_.head(rules_); }

  /// Raw storage for the gradient step, which updates everything in place.
  Eigen::ArrayXXd& mutable_centres() { return centres_; }
  Eigen::ArrayXXd& mutable_sigmas() { return sigmas_; }
  Eigen::ArrayXd& mutable_output_widths() { return output_widths_; }
  /// The cached 1/(σ² + ε): whoever edits σ in place must keep it in step (or RefreshCaches()).
  Eigen::ArrayXXd& mutable_inverse_variances() { return inverse_variances_; }
  /// Recomputes the cached 1/(σ²+ε) and 1/(s²+ε) after in-place edits.
  void RefreshCaches();

 private:
  int inputs_ = 0;
  int capacity_ = 0;
  int rules_ = 0;
  Eigen::ArrayXXd centres_;            // capacity × inputs
  Eigen::ArrayXXd sigmas_;             // capacity × inputs
  Eigen::ArrayXXd inverse_variances_;  // 1 / (σ² + ε), cached: divisions cost more than the rest
  Eigen::ArrayXd output_widths_;       // s_j
  Eigen::ArrayXd inverse_output_weights_;  // 1 / (s_j² + ε)
};

}  // namespace odonata::fuzzy

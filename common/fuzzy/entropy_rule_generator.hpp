#pragma once
// Structure learning: when to create a rule and what it looks like (identifier.md §3).

#include <Eigen/Core>

#include "fuzzy/gaussian_rule_base.hpp"

namespace odonata::fuzzy {

/// How a rule's entropy is measured.
enum class EntropyMeasure {
  kFiring,    ///< H_j = −D_j log₂ D_j, D_j = exp(−F_j): the paper's criterion (default).
  kPerInput,  ///< H_j = −Σ_i D_ji log₂ D_ji, D_ji = exp(−μ_ji): one close input can mask
              ///< novelty in the others, so it grows fewer rules; offered as an option only.
};

/// Parameters of the entropy criterion. Units of widths: scaled regressor units ([−1, 1]).
struct EntropyRuleConfig {
  double threshold = 0.05;  ///< H̄: create a rule when max_j H_j ≤ H̄. Lower ⇒ fewer rules.
  int max_rules = 100;      ///< Hard cap: bounds memory and per-sample time whatever the input.
  double kappa = 0.5;       ///< New width = κ · distance to the nearest centre, per input.
  double sigma_init = 0.3;  ///< Width of the first rule.
  double sigma_min = 0.05;  ///< Floor on any width (also enforced during gradient steps).
  double sigma_max = 1.0;   ///< Ceiling on a new rule's width.
  EntropyMeasure measure = EntropyMeasure::kFiring;
};

/// Decides rule creation from the entropy of the current sample and sizes new rules.
class EntropyRuleGenerator {
 public:
  explicit EntropyRuleGenerator(const EntropyRuleConfig& config) : config_(config) {}

  /// −D log₂ D with D = exp(−F); for F ∈ (0, 1] this is F e^{−F} / ln 2, increasing in F,
  /// so the largest entropy belongs to the most strongly firing rule (0.531 at F = 1).
  static double FiringEntropy(double firing);

  /// max_j H_j for input x (0 when there is no rule).
  double MaxEntropy(const GaussianRuleBase& rules, const Inference& inference,
                    const Eigen::Ref<const Eigen::VectorXd>& x) const;

  /// True when a rule should be created: none exists, or max_j H_j ≤ H̄ — and the cap allows.
  bool ShouldGrow(const GaussianRuleBase& rules, double max_entropy) const;

  /// Widths for a rule centred at x: σ_init for the first rule, otherwise
  /// σ_i = clamp(κ · min_j |x_i − c_ji|, σ_min, σ_max).
  Eigen::VectorXd NewWidths(const GaussianRuleBase& rules,
                            const Eigen::Ref<const Eigen::VectorXd>& x) const;

  const EntropyRuleConfig& config() const { return config_; }
  void set_threshold(double h) { config_.threshold = h; }

 private:
  EntropyRuleConfig config_;
};

}  // namespace odonata::fuzzy

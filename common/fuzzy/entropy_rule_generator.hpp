#pragma once
// Structure learning: when to create a rule, what it looks like, and when a rule has outlived its
// use (docs/identifier.md §4 and §5).

#include <string>

#include <Eigen/Core>

#include "fuzzy/gaussian_rule_base.hpp"

namespace odonata::fuzzy {

/// The largest entropy a rule can have, H at F̄ = 1: 1/(e ln 2). H̄ ≥ this grows on every sample.
inline constexpr double kMaxRuleEntropy = 0.53073784542326;

/// How a rule's entropy is measured.
enum class EntropyMeasure {
  kFiring,    ///< H_j = −D_j log₂ D_j, D_j = exp(−F̄_j), F̄_j = F_j^{1/N} (default).
  kPerInput,  ///< H_j = mean_i −D_ji log₂ D_ji, D_ji = exp(−μ_ji): one close input can mask
              ///< novelty in the others, so it grows fewer rules; offered as an option only.
};

/// Parameters of structure learning. Widths are in scaled regressor units ([−1, 1]).
/// The defaults are the project's one set of defaults (odonata-fit, odonata-identifier and the
/// main job all start from them).
struct EntropyRuleConfig {
  double threshold = 0.1;  ///< H̄ ∈ [0, kMaxRuleEntropy]: grow when max_j H_j ≤ H̄. Lower ⇒ fewer.
  int max_rules = 100;      ///< Hard cap: bounds memory and per-sample time whatever the input.
  double kappa = 1.0;       ///< New width = κ · RMS distance to the nearest rule centre.
  double sigma_init = 0.5;  ///< Width of the first rule.
  double sigma_min = 0.1;   ///< Floor on any width (also enforced during gradient steps).
  double sigma_max = 2.0;   ///< Ceiling on a new rule's width.
  EntropyMeasure measure = EntropyMeasure::kFiring;
  /// A rule older than prune_min_age samples whose utility (mean normalised firing since its
  /// creation, eTS+) is below this is removed; 0 never prunes. With pruning on, a full rule base
  /// replaces its least useful rule instead of refusing to grow.
  double prune_utility = 0.0;
  int prune_min_age = 1000;  ///< Samples a rule lives before it may be pruned or replaced.

  /// Every problem with these values, one per line ("" when valid): the one place they are checked.
  std::string Problems() const;
};

/// The entropy criterion and the sizing of new rules; stateless, the configuration is passed in
/// so H̄ lives in one place (the model's configuration).
class EntropyRuleGenerator {
 public:
  /// −D log₂ D with D = exp(−F); for F ∈ (0, 1] this is F e^{−F} / ln 2, increasing in F,
  /// so the largest entropy belongs to the most strongly firing rule (0.531 at F = 1).
  static double FiringEntropy(double firing);

  /// max_j H_j for input x (0 when there is no rule). The kFiring measure uses the per-input
  /// geometric mean F̄ = exp(−½ min_j d_j / N), so one H̄ is one novelty radius for any N.
  static double MaxEntropy(const EntropyRuleConfig& config, const GaussianRuleBase& rules,
                           const Inference& inference, const Eigen::Ref<const Eigen::VectorXd>& x);

  /// True when a rule is wanted: none exists, or max_j H_j ≤ H̄ (the cap is checked by the caller,
  /// which may make room by replacing a rule).
  static bool IsNovel(const EntropyRuleConfig& config, const GaussianRuleBase& rules,
                      double max_entropy);

  /// Widths for a rule centred at x: σ_init for the first rule, otherwise every input gets
  /// clamp(κ ρ, σ_min, σ_max) with ρ = sqrt(min_j ‖x − c_j‖² / N), the RMS distance to the nearest
  /// centre. A vector distance, so one close coordinate cannot collapse the width.
  static Eigen::VectorXd NewWidths(const EntropyRuleConfig& config, const GaussianRuleBase& rules,
                                   const Eigen::Ref<const Eigen::VectorXd>& x);
};

}  // namespace odonata::fuzzy

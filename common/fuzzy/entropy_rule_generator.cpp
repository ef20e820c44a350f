#include "fuzzy/entropy_rule_generator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace odonata::fuzzy {
namespace {
const double kInvLn2 = 1.0 / std::log(2.0);
// Memory is rules × inputs doubles several times over; a cap beyond this is a typo, not a model.
constexpr int kLargestRuleCap = 100000;
}  // namespace

std::string EntropyRuleConfig::Problems() const {
  std::ostringstream p;
  if (!(threshold >= 0.0 && threshold <= kMaxRuleEntropy))
    p << "entropy threshold H̄ must be in [0, " << kMaxRuleEntropy << "], not " << threshold << "\n";
  if (max_rules < 1 || max_rules > kLargestRuleCap)
    p << "max_rules must be in [1, " << kLargestRuleCap << "], not " << max_rules << "\n";
  if (!(kappa > 0.0 && std::isfinite(kappa))) p << "kappa must be positive, not " << kappa << "\n";
  if (!(sigma_min > 0.0 && std::isfinite(sigma_min)))
    p << "sigma_min must be positive, not " << sigma_min << "\n";
  if (!(sigma_init > 0.0 && std::isfinite(sigma_init)))
    p << "sigma_init must be positive, not " << sigma_init << "\n";
  if (!(sigma_max >= sigma_min && std::isfinite(sigma_max)))
    p << "sigma_max must be finite and ≥ sigma_min, not " << sigma_max << "\n";
  if (!(prune_utility >= 0.0 && prune_utility < 1.0))
    p << "prune_utility must be in [0, 1), not " << prune_utility << "\n";
  if (prune_min_age < 1) p << "prune_min_age must be at least 1, not " << prune_min_age << "\n";
  std::string s = p.str();
  if (!s.empty()) s.pop_back();
  return s;
}

double EntropyRuleGenerator::FiringEntropy(double firing) {
  return firing * std::exp(-firing) * kInvLn2;
}

double EntropyRuleGenerator::MaxEntropy(const EntropyRuleConfig& config,
                                        const GaussianRuleBase& rules, const Inference& inference,
                                        const Eigen::Ref<const Eigen::VectorXd>& x) {
  if (rules.rules() == 0) return 0.0;
  const int n = rules.inputs();
  if (config.measure == EntropyMeasure::kFiring)
    return FiringEntropy(std::exp(-0.5 * inference.min_distance / n));
  double best = 0.0;
  for (int j = 0; j < rules.rules(); ++j) {
    double h = 0.0;
    for (int i = 0; i < n; ++i) {
      const double dx = x(i) - rules.centre(j, i);
      const double s = rules.sigma(j, i);
      h += FiringEntropy(std::exp(-0.5 * dx * dx / (s * s + kEpsilon)));
    }
    best = std::max(best, h / n);
  }
  return best;
}

bool EntropyRuleGenerator::IsNovel(const EntropyRuleConfig& config, const GaussianRuleBase& rules,
                                   double max_entropy) {
  return rules.rules() == 0 || max_entropy <= config.threshold;
}

Eigen::VectorXd EntropyRuleGenerator::NewWidths(const EntropyRuleConfig& config,
                                                const GaussianRuleBase& rules,
                                                const Eigen::Ref<const Eigen::VectorXd>& x) {
  const int n = rules.inputs();
  if (rules.rules() == 0)
    return Eigen::VectorXd::Constant(n, std::max(config.sigma_init, config.sigma_min));
  double nearest = std::numeric_limits<double>::infinity();
  for (int j = 0; j < rules.rules(); ++j) {
    double d2 = 0.0;
    for (int i = 0; i < n; ++i) {
      const double dx = x(i) - rules.centre(j, i);
      d2 += dx * dx;
    }
    nearest = std::min(nearest, d2);
  }
  const double rho = std::sqrt(nearest / n);
  return Eigen::VectorXd::Constant(n, std::clamp(config.kappa * rho, config.sigma_min,
                                                 std::max(config.sigma_min, config.sigma_max)));
}

}  // namespace odonata::fuzzy

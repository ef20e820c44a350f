#include "fuzzy/entropy_rule_generator.hpp"

#include <algorithm>
#include <cmath>

namespace odonata::fuzzy {
namespace {
const double kInvLn2 = 1.0 / std::log(2.0);
}

double EntropyRuleGenerator::FiringEntropy(double firing) {
  return firing * std::exp(-firing) * kInvLn2;
}

double EntropyRuleGenerator::MaxEntropy(const GaussianRuleBase& rules, const Inference& inference,
                                        const Eigen::Ref<const Eigen::VectorXd>& x) const {
  if (rules.rules() == 0) return 0.0;
  if (config_.measure == EntropyMeasure::kFiring) return FiringEntropy(inference.max_firing);
  double best = 0.0;
  for (int j = 0; j < rules.rules(); ++j) {
    double h = 0.0;
    for (int i = 0; i < rules.inputs(); ++i) {
      const double dx = x(i) - rules.centre(j, i);
      const double s = rules.sigma(j, i);
      h += FiringEntropy(std::exp(-0.5 * dx * dx / (s * s + kEpsilon)));
    }
    best = std::max(best, h);
  }
  return best;
}

bool EntropyRuleGenerator::ShouldGrow(const GaussianRuleBase& rules, double max_entropy) const {
  if (rules.rules() >= std::min(config_.max_rules, rules.capacity())) return false;
  return rules.rules() == 0 || max_entropy <= config_.threshold;
}

Eigen::VectorXd EntropyRuleGenerator::NewWidths(const GaussianRuleBase& rules,
                                                const Eigen::Ref<const Eigen::VectorXd>& x) const {
  Eigen::VectorXd sigma(rules.inputs());
  if (rules.rules() == 0) {
    sigma.setConstant(std::max(config_.sigma_init, config_.sigma_min));
    return sigma;
  }
  for (int i = 0; i < rules.inputs(); ++i) {
    const double nearest = (x(i) - rules.centres_of_input(i)).abs().minCoeff();
    sigma(i) = std::clamp(config_.kappa * nearest, config_.sigma_min,
                          std::max(config_.sigma_min, config_.sigma_max));
  }
  return sigma;
}

}  // namespace odonata::fuzzy

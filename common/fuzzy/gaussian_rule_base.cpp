#include "fuzzy/gaussian_rule_base.hpp"

#include <cmath>
#include <limits>
#include "contract/precondition.hpp"

namespace odonata::fuzzy {

GaussianRuleBase::GaussianRuleBase(int inputs, int capacity)
    : inputs_(inputs),
      capacity_(capacity),
      centres_(Eigen::ArrayXXd::Zero(capacity, inputs)),
      sigmas_(Eigen::ArrayXXd::Ones(capacity, inputs)),
      inverse_variances_(Eigen::ArrayXXd::Zero(capacity, inputs)),
      output_widths_(Eigen::ArrayXd::Ones(capacity)),
      inverse_output_weights_(Eigen::ArrayXd::Zero(capacity)) {
  ODONATA_EXPECTS(inputs >= 1 && capacity >= 1);
}

void GaussianRuleBase::AddRule(const Eigen::Ref<const Eigen::VectorXd>& centre,
                               const Eigen::Ref<const Eigen::VectorXd>& sigma,
                               double output_width) {
  ODONATA_EXPECTS(rules_ < capacity_);
  ODONATA_EXPECTS(centre.size() == inputs_ && sigma.size() == inputs_);
  const int j = rules_++;
  for (int i = 0; i < inputs_; ++i) {
    centres_(j, i) = centre(i);
    set_sigma(j, i, sigma(i));
  }
  set_output_width(j, output_width);
}

void GaussianRuleBase::RemoveRule(int rule) {
  ODONATA_EXPECTS(rule >= 0 && rule < rules_);
  const int tail = rules_ - rule - 1;
  if (tail > 0) {
    centres_.middleRows(rule, tail) = centres_.middleRows(rule + 1, tail).eval();
    sigmas_.middleRows(rule, tail) = sigmas_.middleRows(rule + 1, tail).eval();
    inverse_variances_.middleRows(rule, tail) =
        inverse_variances_.middleRows(rule + 1, tail).eval();
    output_widths_.segment(rule, tail) = output_widths_.segment(rule + 1, tail).eval();
    inverse_output_weights_.segment(rule, tail) =
        inverse_output_weights_.segment(rule + 1, tail).eval();
  }
  --rules_;
}

void GaussianRuleBase::set_sigma(int rule, int input, double v) {
  sigmas_(rule, input) = v;
  inverse_variances_(rule, input) = 1.0 / (v * v + kEpsilon);
}

void GaussianRuleBase::set_output_width(int rule, double v) {
  output_widths_(rule) = v;
  inverse_output_weights_(rule) = 1.0 / (v * v + kEpsilon);
}

void GaussianRuleBase::RefreshCaches() {
  const auto r = rules_;
  inverse_variances_.topRows(r) = 1.0 / (sigmas_.topRows(r).square() + kEpsilon);
  inverse_output_weights_.head(r) = 1.0 / (output_widths_.head(r).square() + kEpsilon);
}

void GaussianRuleBase::Evaluate(const Eigen::Ref<const Eigen::VectorXd>& x, Inference* out) const {
  ODONATA_EXPECTS(x.size() == inputs_);
  const int r = rules_;
  if (out->weighted_distance.size() != r) {
    out->weighted_distance.resize(r);
    out->normalized.resize(r);
  }
  if (r == 0) {
    out->min_distance = std::numeric_limits<double>::infinity();
    out->max_firing = 0.0;
    out->nearest_rule = -1;
    return;
  }
  auto& d = out->weighted_distance;
  d = (x(0) - centres_.col(0).head(r)).square() * inverse_variances_.col(0).head(r);
  for (int i = 1; i < inputs_; ++i) {
    d += (x(i) - centres_.col(i).head(r)).square() * inverse_variances_.col(i).head(r);
  }
  Eigen::Index nearest = 0;
  const double dmin = d.minCoeff(&nearest);
  out->min_distance = dmin;
  out->nearest_rule = static_cast<int>(nearest);
  out->max_firing = std::exp(-0.5 * dmin);
  // Shifting by dmin makes the nearest rule's exp exactly 1, so the sum is ≥ 1/(s²+ε) > 0.
  auto& phi = out->normalized;
  phi = (-0.5 * (d - dmin)).exp() * inverse_output_weights_.head(r);
  phi /= phi.sum();
}

}  // namespace odonata::fuzzy

#include "model_export/raw_tsk_model.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <set>
#include <stdexcept>

#include "fuzzy/fuzzy_model_state.hpp"
#include "fuzzy/gaussian_rule_base.hpp"

namespace odonata::model_export {

std::string ClientName(const std::string& name) {
  std::string out;
  for (const char c : name) {
    const auto u = static_cast<unsigned char>(c);
    if (std::isalnum(u))
      out += c;
    else if (c == '+')
      out += 'p';
    else if (c == '-' && !out.empty() && out.back() == 'k')
      out += 'm';
    else if (out.empty() || out.back() != '_')
      out += '_';
  }
  while (!out.empty() && out.back() == '_') out.pop_back();
  if (out.empty() || std::isdigit(static_cast<unsigned char>(out.front()))) out = "v_" + out;
  return out;
}

inference::TskModel ToRawTsk(const sysid::NarxModel& model, int output, const std::string& name) {
  if (output < 0 || output >= model.outputs())
    throw std::invalid_argument("model has no output " + std::to_string(output));
  const fuzzy::FuzzyModel& f = model.model(output);
  const auto& rb = f.rule_base();
  const int n = f.inputs(), r = f.rules();
  if (r == 0)
    throw std::invalid_argument(
        "output " + model.spec().outputs.at(static_cast<std::size_t>(output)) + " has no rule yet");
  const auto& s = model.scaling();
  const double mean = s.output_mean(output), sd = s.output_std(output);

  inference::TskModel m;
  m.name = ClientName(name);
  std::set<std::string> taken;
  for (const auto& raw : model.spec().RegressorNames()) {
    std::string c = ClientName(raw);
    for (int k = 2; !taken.insert(c).second; ++k) c = ClientName(raw) + "_" + std::to_string(k);
    m.input_names.push_back(c);
  }
  for (int i = 0; i < n; ++i) {
    // The training range widened by half its span each side: evalfis refuses inputs outside.
    m.input_low.push_back(s.regressor_mid(i) - 2 * s.regressor_half(i));
    m.input_high.push_back(s.regressor_mid(i) + 2 * s.regressor_half(i));
  }
  m.output_name = ClientName(model.spec().TargetName(output));
  m.output_low = mean - 4 * sd;
  m.output_high = mean + 4 * sd;

  const fuzzy::ConsequentState cs = f.consequent().State();
  m.linear = cs.kind == fuzzy::ConsequentKind::kLinear;
  // φ_j ∝ exp(−½ d_j) / (s_j² + ε): the output widths are rule weights, scaled into (0, 1].
  double max_w = 0;
  for (int j = 0; j < r; ++j) max_w = std::max(max_w, rb.inverse_output_weights()(j));
  for (int j = 0; j < r; ++j) {
    inference::TskRule rule;
    for (int i = 0; i < n; ++i) {
      const double h = s.regressor_half(i);
      rule.centre.push_back(s.regressor_mid(i) + h * rb.centre(j, i));
      // The rule base divides by σ² + ε (fuzzy/gaussian_rule_base.hpp), not σ².
      rule.sigma.push_back(h * std::sqrt(rb.sigma(j, i) * rb.sigma(j, i) + fuzzy::kEpsilon));
    }
    rule.weight = rb.inverse_output_weights()(j) / max_w;
    const auto& a = cs.coefficients.at(static_cast<std::size_t>(j));
    if (m.linear) {
      // y = mean + sd (a0 + Σ a_i (x_i − mid_i) / half_i), constant term last.
      double a0 = a[0];
      for (int i = 0; i < n; ++i) {
        const double ai = a[static_cast<std::size_t>(i) + 1];
        rule.coefficients.push_back(sd * ai / s.regressor_half(i));
        a0 -= ai * s.regressor_mid(i) / s.regressor_half(i);
      }
      rule.coefficients.push_back(mean + sd * a0);
    } else {
      rule.coefficients.push_back(mean + sd * a[0]);
    }
    m.rules.push_back(std::move(rule));
  }
  return m;
}

}  // namespace odonata::model_export

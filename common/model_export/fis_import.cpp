#include "model_export/fis_import.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include "fuzzy/gaussian_rule_base.hpp"
#include "model_export/raw_tsk_model.hpp"
#include "sysid/model/narx_model_state.hpp"

namespace odonata::model_export {
namespace {

// odonata-export names each rule's functions after the rule ("r3"): a placeholder, not a word
// an expert chose, so a model exported and read back carries no names.
bool Placeholder(const std::string& name) {
  return name.size() > 1 && name[0] == 'r' &&
         std::all_of(name.begin() + 1, name.end(), [](char c) { return c >= '0' && c <= '9'; });
}

fuzzy::RuleNames ExpertNames(const inference::TskRule& r) {
  fuzzy::RuleNames names;
  bool any = false;
  for (const auto& t : r.terms) {
    names.terms.push_back(Placeholder(t) ? "" : t);
    any = any || !names.terms.back().empty();
  }
  if (!any) names.terms.clear();
  if (!Placeholder(r.output_term)) names.output = r.output_term;
  return names;
}

}  // namespace

sysid::NarxModel ModelFromTsk(const inference::TskModel& tsk, const sysid::NarxModel& empty,
                              const std::string& source) {
  const auto fail = [&source](const std::string& why) {
    throw std::invalid_argument(source + ": " + why);
  };
  if (empty.outputs() != 1)
    fail("a .fis holds one output; this configuration identifies " +
         std::to_string(empty.outputs()) + " (start it from a saved model instead)");
  const auto names = empty.spec().RegressorNames();
  std::vector<std::string> want;
  for (const auto& n : names) want.push_back(ClientName(n));
  if (tsk.input_names != want) {
    std::string w, g;
    for (const auto& n : want) w += (w.empty() ? "" : ", ") + n;
    for (const auto& n : tsk.input_names) g += (g.empty() ? "" : ", ") + n;
    fail("its inputs are [" + g + "]; the identifier's regressor is [" + w + "], in that order");
  }
  if (tsk.rules.empty()) fail("it has no rule");
  sysid::NarxModelState state = empty.State();
  fuzzy::FuzzyModelState& f = state.models.at(0);
  const sysid::Scaling& s = state.scaling;
  const auto n = static_cast<int>(names.size());
  const double mean = s.output_mean(0), sd = s.output_std(0);
  const bool linear = f.consequent.kind == fuzzy::ConsequentKind::kLinear;
  if (!linear && tsk.linear)
    fail("its rules have linear outputs; the configuration's consequent is singleton");
  if (static_cast<int>(tsk.rules.size()) > f.config.entropy.max_rules)
    fail(std::to_string(tsk.rules.size()) + " rules, over the configuration's max_rules " +
         std::to_string(f.config.entropy.max_rules));
  f.rules.clear();
  f.consequent.coefficients.clear();
  f.consequent.covariances.clear();
  const auto n1 = static_cast<std::size_t>(n + 1);
  for (std::size_t j = 0; j < tsk.rules.size(); ++j) {
    const inference::TskRule& r = tsk.rules[j];
    const std::string rule = "rule " + std::to_string(j + 1) + ": ";
    if (!(r.weight > 0 && r.weight <= 1)) fail(rule + "its weight is not in (0, 1]");
    fuzzy::RuleState rs;
    for (int i = 0; i < n; ++i) {
      const double h = s.regressor_half(i);
      if (std::isinf(r.sigma[static_cast<std::size_t>(i)])) {
        // An input the rule leaves out ("don't care"): a Gaussian so wide that over the
        // identifier's whole range it changes the firing by a factor within 1 − 2·10⁻⁶ of 1.
        rs.centre.push_back(0.0);
        rs.sigma.push_back(kDontCareWidth);
        continue;
      }
      rs.centre.push_back((r.centre[static_cast<std::size_t>(i)] - s.regressor_mid(i)) / h);
      // The rule base divides by σ² + ε: the narrowest width it can stand for is √ε.
      const double scaled = r.sigma[static_cast<std::size_t>(i)] / h;
      const double sigma2 = scaled * scaled - fuzzy::kEpsilon;
      if (!(sigma2 > 0))
        fail(rule + "input " + tsk.input_names[static_cast<std::size_t>(i)] +
             "'s width is narrower than the identifier can hold at its ranges");
      rs.sigma.push_back(std::sqrt(sigma2));
    }
    // Weight w_j = 1 / (s_j² + ε) up to a common factor that cancels: s_j² = 1/w_j − ε.
    rs.output_width = std::sqrt(std::max(1.0 / r.weight - fuzzy::kEpsilon, fuzzy::kEpsilon));
    rs.names = ExpertNames(r);
    f.rules.push_back(std::move(rs));
    // y = b0 + Σ b_i x_i (raw, MATLAB's order: slopes, then the constant) → the scaled network's
    // a0 (first) and a_i: a_i = b_i h_i / sd, a0 = (b0 − mean)/sd + Σ a_i m_i / h_i.
    std::vector<double> a(linear ? n1 : 1, 0.0);
    const double b0 = r.coefficients.back();
    a[0] = (b0 - mean) / sd;
    if (linear && tsk.linear) {
      for (int i = 0; i < n; ++i) {
        const double ai = r.coefficients[static_cast<std::size_t>(i)] * s.regressor_half(i) / sd;
        a[static_cast<std::size_t>(i) + 1] = ai;
        a[0] += ai * s.regressor_mid(i) / s.regressor_half(i);
      }
    }
    f.consequent.coefficients.push_back(a);
    if (linear) {
      std::vector<double> p(n1 * n1, 0.0);
      for (std::size_t d = 0; d < n1; ++d) p[d * n1 + d] = f.consequent.initial_covariance;
      f.consequent.covariances.push_back(std::move(p));
    }
  }
  try {
    return sysid::NarxModel::FromState(state);
  } catch (const std::exception& e) {
    throw std::invalid_argument(source + ": " + e.what());
  }
}

sysid::NarxModel LoadFis(const std::string& path, const sysid::NarxModel& empty) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open");
  inference::TskModel tsk;
  try {
    tsk = inference::TskModel::FromFis(in);
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
  return ModelFromTsk(tsk, empty, path);
}

}  // namespace odonata::model_export

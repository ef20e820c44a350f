#include "snapshot_admission.hpp"

#include <cmath>
#include <vector>

#include "fuzzy/consequent.hpp"

namespace odonata::identifier {
namespace {

std::string Join(const std::vector<std::string>& names) {
  std::string s = "[";
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s + "]";
}

bool AllFinite(const std::vector<double>& v, bool positive) {
  for (const double x : v)
    if (!std::isfinite(x) || (positive && !(x > 0))) return false;
  return true;
}

}  // namespace

std::string SnapshotMismatch(const odonata::model_snapshot_t& s, const IdentifierConfig& config) {
  std::vector<std::string> problems;
  const sysid::RegressorSpec& spec = config.spec;
  if (s.outputs != spec.outputs || s.inputs != spec.inputs) {
    problems.push_back("it models " + Join(s.outputs) + " from " + Join(s.inputs) + ", not " +
                       Join(spec.outputs) + " from " + Join(spec.inputs));
  }
  if (s.output_lags != spec.output_lags || s.input_lags != spec.input_lags ||
      s.delay != spec.delay) {
    problems.push_back("its regressor is ny " + std::to_string(s.output_lags) + ", nu " +
                       std::to_string(s.input_lags) + ", delay " + std::to_string(s.delay) +
                       ", not " + std::to_string(spec.output_lags) + ", " +
                       std::to_string(spec.input_lags) + ", " + std::to_string(spec.delay));
  }
  const auto joined = [&problems] {
    std::string text;
    for (const auto& p : problems) text += (text.empty() ? "" : "; ") + p;
    return text;
  };
  if (!problems.empty()) return joined();  // another experiment's model: nothing else matters
  const int n = spec.size();
  if (s.models.size() != spec.outputs.size())
    problems.push_back("it holds " + std::to_string(s.models.size()) + " models for " +
                       std::to_string(spec.outputs.size()) + " outputs");
  if (s.num_regressors != n || static_cast<int>(s.regressor_mid.size()) != n ||
      static_cast<int>(s.regressor_half.size()) != n) {
    problems.push_back("its scaling has " + std::to_string(s.num_regressors) + " regressors, not " +
                       std::to_string(n));
  } else if (!AllFinite(s.regressor_mid, false) || !AllFinite(s.regressor_half, true) ||
             !AllFinite(s.output_mean, false) || !AllFinite(s.output_std, true)) {
    problems.push_back("its scaling is not finite and positive");
  }
  const std::string kind = fuzzy::ToString(config.model.consequent);
  const int cap = config.model.entropy.max_rules;
  for (const auto& f : s.models) {
    const std::string who = "its model of '" + f.output_name + "'";
    if (f.num_inputs != n)
      problems.push_back(who + " has " + std::to_string(f.num_inputs) + " inputs, not " +
                         std::to_string(n));
    if (f.num_rules < 0 || f.num_rules > cap || f.max_rules < 0 || f.max_rules > cap)
      problems.push_back(who + " claims " + std::to_string(f.num_rules) + " rules (cap " +
                         std::to_string(f.max_rules) + "), beyond this identifier's cap of " +
                         std::to_string(cap));
    if (f.consequent != kind)
      problems.push_back(who + " has " + f.consequent + " consequents, not " + kind);
  }
  return joined();
}

}  // namespace odonata::identifier

#include "model_messages/model_snapshot_message.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "sysid/model/narx_model_state.hpp"

namespace odonata::model_messages {
namespace {

std::vector<double> ToVector(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

Eigen::VectorXd FromVector(const std::vector<double>& v) {
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

odonata::fuzzy_rules_t ToRules(const std::string& output, const fuzzy::FuzzyModelState& s) {
  odonata::fuzzy_rules_t f;
  f.output_name = output;
  f.num_inputs = s.config.inputs;
  f.num_rules = static_cast<int32_t>(s.rules.size());
  for (const auto& r : s.rules) {
    f.centres.push_back(r.centre);
    f.sigmas.push_back(r.sigma);
    f.output_widths.push_back(r.output_width);
    f.utility_sums.push_back(r.utility_sum);
    f.born.push_back(r.born);
  }
  const bool named = std::any_of(s.rules.begin(), s.rules.end(),
                                 [](const fuzzy::RuleState& r) { return !r.names.empty(); });
  f.num_named = named ? f.num_rules : 0;
  for (const auto& r : s.rules) {
    if (!named) break;
    f.output_terms.push_back(r.names.output);
    f.term_names.push_back(r.names.terms.empty()
                               ? std::vector<std::string>(static_cast<std::size_t>(f.num_inputs))
                               : r.names.terms);
  }
  const auto& e = s.config.entropy;
  f.entropy_threshold = e.threshold;
  f.max_rules = e.max_rules;
  f.kappa = e.kappa;
  f.sigma_init = e.sigma_init;
  f.sigma_min = e.sigma_min;
  f.sigma_max = e.sigma_max;
  f.entropy_measure = e.measure == fuzzy::EntropyMeasure::kFiring ? "firing" : "per_input";
  f.prune_utility = e.prune_utility;
  f.prune_min_age = e.prune_min_age;
  f.clock = s.clock;
  f.pruned = s.pruned;
  const auto& a = s.config.rates;
  f.rate_centre = a.centre;
  f.rate_sigma = a.sigma;
  f.rate_output_width = a.output_width;
  f.max_step = a.max_step;
  const fuzzy::ConsequentState& c = s.consequent;
  f.consequent = fuzzy::ToString(c.kind);
  f.nlms_rate = c.kind == fuzzy::ConsequentKind::kSingleton ? c.rate : 0.0;
  f.nlms_regulariser = c.kind == fuzzy::ConsequentKind::kSingleton ? c.regulariser : 0.0;
  f.rls_initial_covariance = c.kind == fuzzy::ConsequentKind::kLinear ? c.initial_covariance : 0.0;
  // One λ travels: the linear learner's own, or the model's (what a singleton would pass on).
  f.rls_forgetting = c.kind == fuzzy::ConsequentKind::kLinear ? c.forgetting : s.config.forgetting;
  f.num_coefficients = c.kind == fuzzy::ConsequentKind::kLinear ? s.config.inputs + 1 : 1;
  f.coefficients = c.coefficients;
  f.covariance_size =
      c.kind == fuzzy::ConsequentKind::kLinear ? f.num_coefficients * f.num_coefficients : 0;
  f.covariances = c.kind == fuzzy::ConsequentKind::kLinear
                      ? c.covariances
                      : std::vector<std::vector<double>>(s.rules.size());
  return f;
}

fuzzy::FuzzyModelState FromRules(const odonata::fuzzy_rules_t& f) {
  // A decoded message's arrays hold what its counts say (lcm-gen sizes them so); a message built
  // in memory may not. FuzzyModel::FromState checks everything else.
  const auto n = static_cast<std::size_t>(f.num_rules < 0 ? 0 : f.num_rules);
  if (f.num_rules < 0 || f.centres.size() != n || f.sigmas.size() != n ||
      f.output_widths.size() != n || f.utility_sums.size() != n || f.born.size() != n ||
      f.coefficients.size() != n || f.covariances.size() != n ||
      (f.num_named != 0 && f.num_named != f.num_rules) ||
      f.output_terms.size() != static_cast<std::size_t>(f.num_named < 0 ? 0 : f.num_named) ||
      f.term_names.size() != f.output_terms.size()) {
    throw std::runtime_error("snapshot: the rule arrays disagree with num_rules");
  }
  fuzzy::FuzzyModelState s;
  fuzzy::FuzzyModelConfig& cfg = s.config;
  cfg.inputs = f.num_inputs;
  auto& e = cfg.entropy;
  e.threshold = f.entropy_threshold;
  e.max_rules = f.max_rules;
  e.kappa = f.kappa;
  e.sigma_init = f.sigma_init;
  e.sigma_min = f.sigma_min;
  e.sigma_max = f.sigma_max;
  if (f.entropy_measure != "firing" && f.entropy_measure != "per_input") {
    throw std::runtime_error("snapshot: entropy measure must be firing or per_input, not '" +
                             f.entropy_measure + "'");
  }
  e.measure = f.entropy_measure == "firing" ? fuzzy::EntropyMeasure::kFiring
                                            : fuzzy::EntropyMeasure::kPerInput;
  e.prune_utility = f.prune_utility;
  e.prune_min_age = f.prune_min_age;
  cfg.rates.centre = f.rate_centre;
  cfg.rates.sigma = f.rate_sigma;
  cfg.rates.output_width = f.rate_output_width;
  cfg.rates.max_step = f.max_step;
  try {
    cfg.consequent = fuzzy::ConsequentKindFromString(f.consequent);
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(std::string("snapshot: ") + ex.what());
  }
  cfg.forgetting = f.rls_forgetting;
  s.clock = f.clock;
  s.pruned = f.pruned;
  for (int r = 0; r < f.num_rules; ++r) {
    const auto k = static_cast<std::size_t>(r);
    s.rules.push_back(
        {f.centres[k], f.sigmas[k], f.output_widths[k], f.utility_sums[k], f.born[k], {}});
    if (f.num_named > 0) {
      fuzzy::RuleNames& names = s.rules.back().names;
      names.output = f.output_terms[k];
      // A rule with no term named carries none, as in a model file.
      if (std::any_of(f.term_names[k].begin(), f.term_names[k].end(),
                      [](const std::string& t) { return !t.empty(); }))
        names.terms = f.term_names[k];
    }
  }
  fuzzy::ConsequentState& c = s.consequent;
  c.kind = cfg.consequent;
  c.coefficients = f.coefficients;
  if (c.kind == fuzzy::ConsequentKind::kSingleton) {
    c.rate = f.nlms_rate;
    c.regulariser = f.nlms_regulariser;
  } else {
    c.initial_covariance = f.rls_initial_covariance;
    c.forgetting = f.rls_forgetting;
    c.covariances = f.covariances;
  }
  return s;
}

}  // namespace

odonata::model_snapshot_t EncodeSnapshot(const sysid::NarxModel& model) {
  const sysid::NarxModelState s = model.State();
  odonata::model_snapshot_t m;
  m.utime = 0;
  m.seq = 0;
  m.samples_learned = 0;
  m.learned_through = -1;
  m.learning = 1;  // the identifier sets both from its learner
  m.output_lags = s.spec.output_lags;
  m.input_lags = s.spec.input_lags;
  m.delay = s.spec.delay;
  m.outputs = s.spec.outputs;
  m.num_outputs = static_cast<int32_t>(m.outputs.size());
  m.inputs = s.spec.inputs;
  m.num_inputs = static_cast<int32_t>(m.inputs.size());
  m.regressor_mid = ToVector(s.scaling.regressor_mid);
  m.regressor_half = ToVector(s.scaling.regressor_half);
  m.num_regressors = static_cast<int32_t>(m.regressor_mid.size());
  m.output_mean = ToVector(s.scaling.output_mean);
  m.output_std = ToVector(s.scaling.output_std);
  const auto no = static_cast<Eigen::Index>(m.outputs.size());
  m.output_lower = ToVector(
      s.limits.any() ? s.limits.lower
                     : Eigen::VectorXd::Constant(no, -std::numeric_limits<double>::infinity()));
  m.output_upper = ToVector(
      s.limits.any() ? s.limits.upper
                     : Eigen::VectorXd::Constant(no, std::numeric_limits<double>::infinity()));
  m.envelope_lower = ToVector(s.envelope.lower);
  m.envelope_upper = ToVector(s.envelope.upper);
  m.envelope_regressors = static_cast<int32_t>(m.envelope_lower.size());
  m.envelope_outputs = static_cast<int32_t>(s.envelope.outputs.size());
  for (const sysid::OutputEnvelope& e : s.envelope.outputs) {
    m.envelope_linear.insert(m.envelope_linear.end(), e.linear.data(),
                             e.linear.data() + e.linear.size());
    m.envelope_radius_widths.push_back(e.radius_widths);
  }
  m.envelope_coefficients = static_cast<int32_t>(m.envelope_linear.size());
  for (std::size_t o = 0; o < s.models.size(); ++o)
    m.models.push_back(ToRules(m.outputs[o], s.models[o]));
  return m;
}

sysid::NarxModel DecodeSnapshot(const odonata::model_snapshot_t& m) {
  sysid::NarxModelState s;
  s.spec.output_lags = m.output_lags;
  s.spec.input_lags = m.input_lags;
  s.spec.delay = m.delay;
  s.spec.outputs = m.outputs;
  s.spec.inputs = m.inputs;
  s.scaling.regressor_mid = FromVector(m.regressor_mid);
  s.scaling.regressor_half = FromVector(m.regressor_half);
  s.scaling.output_mean = FromVector(m.output_mean);
  s.scaling.output_std = FromVector(m.output_std);
  s.limits.lower = FromVector(m.output_lower);
  s.limits.upper = FromVector(m.output_upper);
  s.envelope.lower = FromVector(m.envelope_lower);
  s.envelope.upper = FromVector(m.envelope_upper);
  if (m.envelope_outputs > 0) {
    // Each output's coefficients in turn: the sizes are checked here, the values by FromState.
    const auto terms = static_cast<std::size_t>(m.num_regressors) + 1;
    if (m.num_regressors < 0 ||
        m.envelope_linear.size() != static_cast<std::size_t>(m.envelope_outputs) * terms)
      throw std::runtime_error("snapshot envelope: " + std::to_string(m.envelope_linear.size()) +
                               " coefficients for " + std::to_string(m.envelope_outputs) +
                               " outputs of " + std::to_string(terms) + " terms");
    for (std::size_t o = 0; o < static_cast<std::size_t>(m.envelope_outputs); ++o) {
      sysid::OutputEnvelope e;
      e.linear = Eigen::Map<const Eigen::VectorXd>(m.envelope_linear.data() + o * terms,
                                                   static_cast<Eigen::Index>(terms));
      e.radius_widths = m.envelope_radius_widths[o];
      s.envelope.outputs.push_back(std::move(e));
    }
  }
  for (const auto& f : m.models) s.models.push_back(FromRules(f));
  return sysid::NarxModel::FromState(s);
}

}  // namespace odonata::model_messages

// The fuzzy model as a plain state (FuzzyModelState) and as JSON, both ways: what a model file,
// a bus snapshot and a refit's copy are made of. Reading checks every field (sizes, finite and
// sane values) and names the one at fault, before any rule is built.

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

#include "fuzzy/fuzzy_model.hpp"
#include "fuzzy/fuzzy_model_state.hpp"
#include "io/json_integer.hpp"

namespace odonata::fuzzy {

FuzzyModelState FuzzyModel::State() const {
  FuzzyModelState s;
  s.config = config_;
  s.clock = clock_;
  s.pruned = pruned_;
  for (int r = 0; r < rules_.rules(); ++r) {
    RuleState rule;
    for (int i = 0; i < config_.inputs; ++i) {
      rule.centre.push_back(rules_.centre(r, i));
      rule.sigma.push_back(rules_.sigma(r, i));
    }
    rule.output_width = rules_.output_width(r);
    rule.utility_sum = utility_sum_(r);
    rule.born = born_(r);
    rule.names = names_[static_cast<std::size_t>(r)];
    s.rules.push_back(std::move(rule));
  }
  s.consequent = consequent_->State();
  return s;
}

FuzzyModel FuzzyModel::FromState(const FuzzyModelState& s) {
  try {
    // Validate before anything is allocated: a hostile file or snapshot may claim a huge cap.
    const std::string problems = s.config.Problems();
    if (!problems.empty()) throw std::runtime_error(problems);
    if (s.consequent.kind != s.config.consequent) {
      throw std::runtime_error("the consequent differs from the configured kind");
    }
    const int inputs = s.config.inputs;
    if (static_cast<int>(s.rules.size()) > s.config.entropy.max_rules) {
      throw std::runtime_error("more rules than entropy.max_rules");
    }
    FuzzyModel model(s.config);
    model.clock_ = s.clock;
    model.pruned_ = s.pruned;
    for (const RuleState& rule : s.rules) {
      if (static_cast<int>(rule.centre.size()) != inputs ||
          static_cast<int>(rule.sigma.size()) != inputs) {
        throw std::runtime_error("a rule has the wrong number of centres or widths");
      }
      for (double v : rule.centre)
        if (!(std::abs(v) <= kMaxRuleExtent))
          throw std::runtime_error("a rule centre is not finite or beyond ±1e6 (scaled units)");
      // The learners never narrow a width below sigma_min (a width of 1e-300 overflowed the
      // premise gradients); within rounding of it, a model written and read back passes.
      const double narrowest = s.config.entropy.sigma_min * (1.0 - 1e-9);
      for (double v : rule.sigma)
        if (!(v >= narrowest && v <= kMaxRuleExtent))
          throw std::runtime_error("a rule width " + std::to_string(v) +
                                   " is not in [sigma_min, 1e6] (scaled units; sigma_min " +
                                   std::to_string(s.config.entropy.sigma_min) + ")");
      if (!(rule.output_width > 0.0 && rule.output_width <= kMaxRuleExtent) ||
          !std::isfinite(rule.utility_sum)) {
        throw std::runtime_error(
            "a rule's output width is not in (0, 1e6] or its utility is not "
            "finite");
      }
      const std::string names = rule.names.Problem(inputs);
      if (!names.empty()) throw std::runtime_error("a rule's names: " + names);
      const int k = model.rules_.rules();
      model.rules_.AddRule(Eigen::Map<const Eigen::VectorXd>(rule.centre.data(), inputs),
                           Eigen::Map<const Eigen::VectorXd>(rule.sigma.data(), inputs),
                           rule.output_width);
      model.utility_sum_(k) = rule.utility_sum;
      model.born_(k) = rule.born;
      model.names_.push_back(rule.names);
    }
    model.consequent_ = ConsequentFromState(s.consequent, inputs, s.config.entropy.max_rules);
    if (model.consequent_->rules() != model.rules_.rules()) {
      throw std::runtime_error("consequent count differs from the rule count");
    }
    return model;
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(std::string("fuzzy model: ") + ex.what());
  } catch (const std::runtime_error& ex) {
    throw std::runtime_error(std::string("fuzzy model: ") + ex.what());
  }
}

nlohmann::json FuzzyModel::ToJson() const {
  const FuzzyModelState s = State();
  nlohmann::json j;
  j["inputs"] = s.config.inputs;
  const auto& e = s.config.entropy;
  j["entropy"] = {{"threshold", e.threshold},
                  {"max_rules", e.max_rules},
                  {"kappa", e.kappa},
                  {"sigma_init", e.sigma_init},
                  {"sigma_min", e.sigma_min},
                  {"sigma_max", e.sigma_max},
                  {"measure", e.measure == EntropyMeasure::kFiring ? "firing" : "per_input"},
                  {"prune_utility", e.prune_utility},
                  {"prune_min_age", e.prune_min_age}};
  j["forgetting"] = s.config.forgetting;
  j["clock"] = s.clock;
  j["pruned"] = s.pruned;
  const auto& a = s.config.rates;
  j["rates"] = {{"centre", a.centre},
                {"sigma", a.sigma},
                {"output_width", a.output_width},
                {"max_step", a.max_step}};
  nlohmann::json rules = nlohmann::json::array();
  for (const RuleState& r : s.rules) {
    rules.push_back({{"centre", r.centre},
                     {"sigma", r.sigma},
                     {"output_width", r.output_width},
                     {"utility_sum", r.utility_sum},
                     {"born", r.born}});
    // Only an expert's rules carry names, so every other model file reads as it always did.
    if (!r.names.empty())
      rules.back()["names"] = {{"terms", r.names.terms}, {"output", r.names.output}};
  }
  j["rules"] = rules;
  const ConsequentState& c = s.consequent;
  nlohmann::json cj;
  cj["kind"] = ToString(c.kind);
  if (c.kind == ConsequentKind::kSingleton) {
    cj["rate"] = c.rate;
    cj["regulariser"] = c.regulariser;
    std::vector<double> centres;
    for (const auto& b : c.coefficients) centres.push_back(b.at(0));
    cj["centres"] = centres;
  } else {
    cj["initial_covariance"] = c.initial_covariance;
    cj["forgetting"] = c.forgetting;
    cj["coefficients"] = c.coefficients;
    cj["covariances"] = c.covariances;
  }
  j["consequent"] = cj;
  return j;
}

FuzzyModel FuzzyModel::FromJson(const nlohmann::json& j) { return FromState(StateFromJson(j)); }

FuzzyModelState FuzzyModel::StateFromJson(const nlohmann::json& j) {
  FuzzyModelState s;
  try {
    FuzzyModelConfig& cfg = s.config;
    cfg.inputs = io::JsonInteger<int>(j.at("inputs"), "inputs");
    const auto& e = j.at("entropy");
    cfg.entropy.threshold = e.at("threshold").get<double>();
    cfg.entropy.max_rules = io::JsonInteger<int>(e.at("max_rules"), "max_rules");
    cfg.entropy.kappa = e.at("kappa").get<double>();
    cfg.entropy.sigma_init = e.at("sigma_init").get<double>();
    cfg.entropy.sigma_min = e.at("sigma_min").get<double>();
    cfg.entropy.sigma_max = e.at("sigma_max").get<double>();
    const auto measure = e.at("measure").get<std::string>();
    if (measure != "firing" && measure != "per_input") {
      throw std::runtime_error("entropy.measure must be firing or per_input, not '" + measure +
                               "'");
    }
    cfg.entropy.measure = measure == "firing" ? EntropyMeasure::kFiring : EntropyMeasure::kPerInput;
    const auto& a = j.at("rates");
    cfg.rates.centre = a.at("centre").get<double>();
    cfg.rates.sigma = a.at("sigma").get<double>();
    cfg.rates.output_width = a.at("output_width").get<double>();
    cfg.rates.max_step = a.at("max_step").get<double>();
    // Fields added after version 1 was first written default to what older models did.
    cfg.entropy.prune_utility = e.value("prune_utility", 0.0);
    cfg.entropy.prune_min_age = io::JsonInteger<int>(e, "prune_min_age", cfg.entropy.prune_min_age);
    const auto& cons = j.at("consequent");
    cfg.consequent = ConsequentKindFromString(cons.at("kind").get<std::string>());
    cfg.forgetting = j.value("forgetting", cons.value("forgetting", 1.0));
    s.clock = io::JsonInteger<int64_t>(j, "clock", 0);
    s.pruned = io::JsonInteger<int64_t>(j, "pruned", 0);
    const auto& rules = j.at("rules");
    // Checked before the rules are read: a hostile file may hold millions.
    if (cfg.entropy.max_rules >= 0 &&
        rules.size() > static_cast<std::size_t>(cfg.entropy.max_rules)) {
      throw std::runtime_error("more rules than entropy.max_rules");
    }
    for (const auto& rule : rules) {
      RuleState r;
      r.centre = rule.at("centre").get<std::vector<double>>();
      r.sigma = rule.at("sigma").get<std::vector<double>>();
      r.output_width = rule.at("output_width").get<double>();
      r.utility_sum = rule.value("utility_sum", 0.0);
      r.born = io::JsonInteger<int64_t>(rule, "born", s.clock);
      if (rule.contains("names")) {
        const auto& names = rule.at("names");
        r.names.terms = names.value("terms", std::vector<std::string>{});
        r.names.output = names.value("output", std::string());
      }
      s.rules.push_back(std::move(r));
    }
    ConsequentState& c = s.consequent;
    c.kind = cfg.consequent;
    if (c.kind == ConsequentKind::kSingleton) {
      c.rate = cons.at("rate").get<double>();
      c.regulariser = cons.at("regulariser").get<double>();
      for (double b : cons.at("centres").get<std::vector<double>>()) c.coefficients.push_back({b});
    } else {
      c.initial_covariance = cons.at("initial_covariance").get<double>();
      c.forgetting = cons.at("forgetting").get<double>();
      c.coefficients = cons.at("coefficients").get<std::vector<std::vector<double>>>();
      c.covariances = cons.at("covariances").get<std::vector<std::vector<double>>>();
    }
  } catch (const nlohmann::json::exception& ex) {
    throw std::runtime_error(std::string("fuzzy model: ") + ex.what());
  } catch (const std::invalid_argument& ex) {
    throw std::runtime_error(std::string("fuzzy model: ") + ex.what());
  }
  return s;
}

}  // namespace odonata::fuzzy

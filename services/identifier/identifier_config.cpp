#include "identifier_config.hpp"

#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

namespace odonata::identifier {

namespace {

IdentifierConfig FromJson(const nlohmann::json& j, const std::string& path);

}  // namespace

IdentifierConfig LoadIdentifierConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path + ": cannot open configuration");
  nlohmann::json j;
  try {
    in >> j;
  } catch (const std::exception& e) {
    throw std::runtime_error(path + ": not valid JSON: " + e.what());
  }
  return FromJson(j, path);
}

IdentifierConfig DefaultIdentifierConfig() {
  return FromJson(nlohmann::json::parse(ExampleIdentifierConfig()), "built-in configuration");
}

namespace {

IdentifierConfig FromJson(const nlohmann::json& j, const std::string& path) {
  IdentifierConfig c;
  std::string problems;
  auto problem = [&problems](const std::string& p) { problems += "\n  - " + p; };
  try {
    c.instance = j.value("instance", c.instance);
    c.spec.outputs = j.value("outputs", std::vector<std::string>{});
    c.spec.inputs = j.value("inputs", std::vector<std::string>{});
    c.spec.output_lags = j.value("ny", 1);
    c.spec.input_lags = j.value("nu", 1);
    c.spec.delay = j.value("delay", 1);
    const std::string p = c.spec.Problems();
    if (!p.empty()) problem(p);
    const std::string kind =
        j.value("consequent", std::string(fuzzy::ToString(c.model.consequent)));
    if (kind != "singleton" && kind != "linear")
      problem("consequent must be singleton or linear");
    else
      c.model.consequent = fuzzy::ConsequentKindFromString(kind);
    auto& e = c.model.entropy;
    e.threshold = j.value("entropy_threshold", e.threshold);
    e.max_rules = j.value("max_rules", e.max_rules);
    e.kappa = j.value("kappa", e.kappa);
    e.sigma_init = j.value("sigma_init", e.sigma_init);
    e.sigma_min = j.value("sigma_min", e.sigma_min);
    e.sigma_max = j.value("sigma_max", e.sigma_max);
    e.prune_utility = j.value("prune_utility", e.prune_utility);
    e.prune_min_age = j.value("prune_min_age", e.prune_min_age);
    c.model.forgetting = j.value("forgetting", c.model.forgetting);
    // The fuzzy core owns the ranges of its parameters; report its words, one per line.
    std::string model_problems = c.model.Problems();
    for (std::size_t pos; !model_problems.empty();) {
      pos = model_problems.find('\n');
      problem(model_problems.substr(0, pos));
      model_problems = pos == std::string::npos ? "" : model_problems.substr(pos + 1);
    }
    c.snapshot_period_s = j.value("snapshot_period_s", c.snapshot_period_s);
    c.snapshot_every_samples = j.value("snapshot_every_samples", c.snapshot_every_samples);
    c.resume_wait_s = j.value("resume_wait_s", c.resume_wait_s);
    if (j.contains("ranges")) c.ranges = sysid::RangesFromJson(j["ranges"]);
    if (j.contains("channels")) c.channels.Override(j["channels"]);
    try {
      if (p.empty()) sysid::ScalingFromRanges(c.spec, c.ranges);
    } catch (const std::exception& e) {
      problem(std::string(e.what()) + " (add it to \"ranges\")");
    }
  } catch (const std::exception& e) {
    problem(e.what());
  }
  if (!problems.empty()) throw std::runtime_error(path + ": invalid configuration:" + problems);
  return c;
}

}  // namespace

std::string ExampleIdentifierConfig() {
  // The shared defaults (fuzzy::FuzzyModelConfig), so --print-config, odonata-fit and the main
  // job start from the same values; only the signals and their ranges are an example.
  const fuzzy::FuzzyModelConfig d;
  nlohmann::ordered_json j;
  j["instance"] = "identifier";
  j["outputs"] = {"roll_rad"};
  // The open-loop roll loop of the roll preset: the command the wings applied (the excitation
  // plus the onboard hold's correction), from DIMAV_BEAT_STATE.
  j["inputs"] = {"u_roll_applied_rad"};
  j["ny"] = 1;
  j["nu"] = 1;
  j["delay"] = 1;
  j["consequent"] = fuzzy::ToString(d.consequent);
  j["entropy_threshold"] = d.entropy.threshold;
  j["max_rules"] = d.entropy.max_rules;
  j["kappa"] = d.entropy.kappa;
  j["sigma_init"] = d.entropy.sigma_init;
  j["sigma_min"] = d.entropy.sigma_min;
  j["sigma_max"] = d.entropy.sigma_max;
  j["forgetting"] = d.forgetting;
  j["prune_utility"] = d.entropy.prune_utility;
  j["prune_min_age"] = d.entropy.prune_min_age;
  j["ranges"] = {{"roll_rad", {-0.3, 0.3}}, {"u_roll_applied_rad", {-0.27, 0.27}}};
  j["snapshot_period_s"] = 1.0;
  j["snapshot_every_samples"] = 100;
  j["resume_wait_s"] = 1.0;
  j["channels"] = {
      {"command", "DIMAV_COMMAND"}, {"state", "DIMAV_STATE"}, {"beat_state", "DIMAV_BEAT_STATE"}};
  return j.dump(2) + "\n";
}

}  // namespace odonata::identifier

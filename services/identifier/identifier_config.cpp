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
    const std::string kind = j.value("consequent", std::string("singleton"));
    if (kind != "singleton" && kind != "linear")
      problem("consequent must be singleton or linear");
    else
      c.model.consequent = fuzzy::ConsequentKindFromString(kind);
    c.model.entropy.threshold = j.value("entropy_threshold", c.model.entropy.threshold);
    c.model.entropy.max_rules = j.value("max_rules", c.model.entropy.max_rules);
    if (c.model.entropy.max_rules < 1) problem("max_rules must be at least 1");
    if (c.model.entropy.threshold < 0) problem("entropy_threshold must be ≥ 0");
    c.snapshot_period_s = j.value("snapshot_period_s", c.snapshot_period_s);
    c.snapshot_every_samples = j.value("snapshot_every_samples", c.snapshot_every_samples);
    c.model.entropy.kappa = j.value("kappa", c.model.entropy.kappa);
    c.model.entropy.sigma_init = j.value("sigma_init", c.model.entropy.sigma_init);
    c.model.entropy.sigma_min = j.value("sigma_min", c.model.entropy.sigma_min);
    if (!(c.model.entropy.kappa > 0) || !(c.model.entropy.sigma_min > 0))
      problem("kappa and sigma_min must be positive");
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
  return R"({
  "instance": "identifier",
  "outputs": ["roll_rad"],
  "inputs": ["u_roll_rad"],
  "ny": 1, "nu": 1, "delay": 1,
  "consequent": "singleton",
  "entropy_threshold": 0.01,
  "max_rules": 100,
  "ranges": {"roll_rad": [-0.3, 0.3], "u_roll_rad": [-0.27, 0.27]},
  "kappa": 1.0, "sigma_min": 0.3,
  "snapshot_period_s": 1.0,
  "snapshot_every_samples": 100,
  "resume_wait_s": 1.0,
  "channels": {"command": "DIMAV_COMMAND", "state": "DIMAV_STATE"}
}
)";
}

}  // namespace odonata::identifier

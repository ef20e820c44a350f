#include "identifier_config/identifier_config.hpp"

#include "sysid/online/learner_settings.hpp"

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <functional>
#include <limits>
#include <set>
#include <stdexcept>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/parse_command_line.hpp"
#include "io/json_integer.hpp"

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

IdentifierConfig ParseIdentifierConfig(const std::string& text, const std::string& origin) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const std::exception& e) {
    throw std::runtime_error(origin + ": not valid JSON: " + e.what());
  }
  return FromJson(j, origin);
}

IdentifierConfig DefaultIdentifierConfig() {
  return FromJson(nlohmann::json::parse(ExampleIdentifierConfig()), "built-in configuration");
}

namespace {

// Every key the file may hold: any other is a typo (entropy_treshold) that would otherwise be
// silently ignored.
const std::set<std::string> kKnownKeys = {"instance",
                                          "outputs",
                                          "inputs",
                                          "ny",
                                          "nu",
                                          "delay",
                                          "consequent",
                                          "entropy_threshold",
                                          "max_rules",
                                          "kappa",
                                          "sigma_init",
                                          "sigma_min",
                                          "sigma_max",
                                          "prune_utility",
                                          "prune_min_age",
                                          "forgetting",
                                          "snapshot_period_s",
                                          "snapshot_every_samples",
                                          "resume_wait_s",
                                          "decimate",
                                          "max_gap",
                                          "refit_first",
                                          "refit_every",
                                          "refit_buffer",
                                          "refit_history",
                                          "refit_at_freeze",
                                          "refit_threads",
                                          "refit_horizon",
                                          "source",
                                          "ranges",
                                          "channels"};

// An integer field within [lo, hi]: a fraction, 1.3e29 or 4294967297 for an int is a problem,
// never a silent conversion (io::JsonInteger reads it).
template <class Int>
Int IntegerField(const nlohmann::json& j, const std::string& key, Int fallback, int64_t lo,
                 int64_t hi, const std::function<void(const std::string&)>& problem) {
  if (!j.contains(key)) return fallback;
  int64_t v = 0;
  try {
    v = io::JsonInteger<int64_t>(j.at(key), key);
  } catch (const std::runtime_error& e) {
    problem(e.what());
    return fallback;
  }
  if (v < lo || v > hi) {
    problem("\"" + key + "\" must be in [" + std::to_string(lo) + ", " + std::to_string(hi) +
            "], not " + std::to_string(v));
    return fallback;
  }
  return static_cast<Int>(v);
}

namespace {

// " (did you mean \"refit_horizon\"?)" for the known key nearest a mistyped one, when it is near
// enough to be a typo (at most a third of its letters, and two, changed); "" otherwise.
std::string DidYouMean(const std::string& key) {
  std::string best;
  std::size_t best_distance = std::min<std::size_t>(2, key.size() / 3);
  for (const std::string& known : kKnownKeys) {
    const std::size_t d = cli::EditDistance(key, known);
    if (d <= best_distance && (best.empty() || d < best_distance)) {
      best = known;
      best_distance = d;
    }
  }
  return best.empty() ? "" : " (did you mean \"" + best + "\"?)";
}

}  // namespace

IdentifierConfig FromJson(const nlohmann::json& j, const std::string& path) {
  IdentifierConfig c;
  std::string problems;
  auto problem = [&problems](const std::string& p) { problems += "\n  - " + p; };
  try {
    if (!j.is_object()) throw std::runtime_error("the configuration must be a JSON object");
    for (const auto& [key, value] : j.items())
      if (kKnownKeys.count(key) == 0) problem("unknown key \"" + key + "\"" + DidYouMean(key));
    c.instance = j.value("instance", c.instance);
    c.spec.outputs = j.value("outputs", std::vector<std::string>{});
    c.spec.inputs = j.value("inputs", std::vector<std::string>{});
    const int max_lags = sysid::RegressorSpec::kMaxLags;
    c.spec.output_lags = IntegerField<int>(j, "ny", 1, 0, max_lags, problem);
    c.spec.input_lags = IntegerField<int>(j, "nu", 1, 0, max_lags, problem);
    c.spec.delay = IntegerField<int>(j, "delay", 1, 0, 1, problem);
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
    e.max_rules = IntegerField<int>(j, "max_rules", e.max_rules, 1, 1000000, problem);
    e.kappa = j.value("kappa", e.kappa);
    e.sigma_init = j.value("sigma_init", e.sigma_init);
    e.sigma_min = j.value("sigma_min", e.sigma_min);
    e.sigma_max = j.value("sigma_max", e.sigma_max);
    e.prune_utility = j.value("prune_utility", e.prune_utility);
    e.prune_min_age = IntegerField<int>(j, "prune_min_age", e.prune_min_age, 0,
                                        std::numeric_limits<int>::max(), problem);
    c.model.forgetting = j.value("forgetting", c.model.forgetting);
    // The fuzzy core owns the ranges of its parameters; report its words, one per line.
    std::string model_problems = c.model.Problems();
    for (std::size_t pos; !model_problems.empty();) {
      pos = model_problems.find('\n');
      problem(model_problems.substr(0, pos));
      model_problems = pos == std::string::npos ? "" : model_problems.substr(pos + 1);
    }
    c.snapshot_period_s = j.value("snapshot_period_s", c.snapshot_period_s);
    c.snapshot_every_samples =
        IntegerField<int64_t>(j, "snapshot_every_samples", c.snapshot_every_samples, 0,
                              std::numeric_limits<int64_t>::max(), problem);
    c.resume_wait_s = j.value("resume_wait_s", c.resume_wait_s);
    c.decimate = IntegerField<int>(j, "decimate", c.decimate, 1, 100000, problem);
    c.max_gap = IntegerField<int>(j, "max_gap", c.max_gap, 0, 1000, problem);
    const int64_t most = 100000000;  // 10⁸ samples: beyond any buffer a board can hold
    c.refit.first = IntegerField<int64_t>(j, "refit_first", c.refit.first, 0, most, problem);
    c.refit.every = IntegerField<int64_t>(j, "refit_every", c.refit.every, 0, most, problem);
    c.refit.buffer = IntegerField<int64_t>(j, "refit_buffer", c.refit.buffer, 1, most, problem);
    if (j.contains("refit_history")) {
      const nlohmann::json& h = j.at("refit_history");
      if (h.is_number() && h.get<double>() >= 0.0 && h.get<double>() <= 1.0)
        c.refit.history = h.get<double>();
      else
        problem(
            "\"refit_history\" must be a number in [0, 1] (the share of refit_buffer kept "
            "spread over the run), not " +
            h.dump());
    }
    c.refit.at_freeze = j.value("refit_at_freeze", c.refit.at_freeze);
    c.refit.threads = IntegerField<unsigned>(j, "refit_threads", c.refit.threads, 0, 1024, problem);
    c.refit.horizon = IntegerField<int>(j, "refit_horizon", c.refit.horizon, 0, 1000000, problem);
    if (c.refit.horizon == 1)
      problem(
          "\"refit_horizon\" must be 0 (refits choose in free run) or K >= 2 (K steps ahead), "
          "not 1");
    const std::string source = j.value("source", std::string("dimav"));
    if (source == "signals")
      c.source = SampleSource::kSignals;
    else if (source != "dimav")
      problem(
          "\"source\" must be \"dimav\" (commands and states) or \"signals\" (signals_t), "
          "not \"" +
          source + "\"");
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

nlohmann::ordered_json IdentifierConfigToJson(const IdentifierConfig& c) {
  nlohmann::ordered_json j;
  j["instance"] = c.instance;
  j["outputs"] = c.spec.outputs;
  j["inputs"] = c.spec.inputs;
  j["ny"] = c.spec.output_lags;
  j["nu"] = c.spec.input_lags;
  j["delay"] = c.spec.delay;
  const nlohmann::ordered_json learner = sysid::LearnerSettingsJson(c.model, c.refit);
  for (const auto& [key, value] : learner.items()) j[key] = value;
  j["ranges"] = sysid::RangesToJson(c.ranges);
  j["snapshot_period_s"] = c.snapshot_period_s;
  j["snapshot_every_samples"] = c.snapshot_every_samples;
  j["resume_wait_s"] = c.resume_wait_s;
  // One sample per block of this many (5 learns at 20 Hz from a 100 Hz plant).
  j["decimate"] = c.decimate;
  // Up to this many samples lost in a row are bridged by interpolation (odonata-fit --max-gap).
  j["max_gap"] = c.max_gap;
  // "dimav": the DI-MAV's commands, states and beat states; "signals": any vehicle's signals_t.
  const bool signals = c.source == SampleSource::kSignals;
  j["source"] = signals ? "signals" : "dimav";
  // The channels it reads, and any other renamed.
  const std::vector<std::string> reads =
      signals ? std::vector<std::string>{"signals"}
              : std::vector<std::string>{"command", "state", "beat_state"};
  j["channels"] = c.channels.ToJson(bus::ChannelConfig{}, reads);
  return j;
}

std::string ExampleIdentifierConfig() {
  // The shared defaults (fuzzy::FuzzyModelConfig, RefitSchedule::IdentifierDefault), so
  // --print-config, odonata-fit and the main job start from the same values; only the signals
  // and their ranges are an example: the open-loop roll loop of the roll preset, from the
  // command the wings applied (the excitation plus the onboard hold's correction, on
  // DIMAV_BEAT_STATE).
  IdentifierConfig c;
  c.spec.outputs = {"roll_rad"};
  c.spec.inputs = {"u_roll_applied_rad"};
  c.spec.output_lags = 1;
  c.spec.input_lags = 1;
  c.spec.delay = 1;
  c.ranges = {{"roll_rad", {-0.3, 0.3}}, {"u_roll_applied_rad", {-0.27, 0.27}}};
  return IdentifierConfigToJson(c).dump(2) + "\n";
}

}  // namespace odonata::identifier

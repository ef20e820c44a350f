#include "plant/plant_config.hpp"

#include <cmath>
#include <fstream>
#include <nlohmann/json.hpp>

#include <set>
#include <sstream>
#include <vector>
#include "io/json_integer.hpp"

namespace odonata::plant {
namespace {

using nlohmann::json;

const std::array<const char*, kWingCount> kHingeKeys = {"fore_left", "hind_left", "hind_right",
                                                        "fore_right"};

// Source groups every configuration must document.
const std::array<const char*, 12> kSourceKeys = {"mass_kg",
                                                 "inertia",
                                                 "gravity_mps2",
                                                 "air_density_kgpm3",
                                                 "wing",
                                                 "hinges_m",
                                                 "fore_hind_phase_rad",
                                                 "nominal_command",
                                                 "limits",
                                                 "integration",
                                                 "ground",
                                                 "divergence"};

// Reads keys from JSON objects and collects every problem instead of stopping at the first.
class Reader {
 public:
  explicit Reader(std::string source) : source_(std::move(source)) {}

  const json* Object(const json& parent, const std::string& key, const std::string& path) {
    const json* v = Find(parent, key, path);
    if (v && !v->is_object()) {
      Problem(path + key, "must be an object");
      return nullptr;
    }
    return v;
  }
  double Number(const json& parent, const std::string& key, const std::string& path) {
    const json* v = Find(parent, key, path);
    if (!v) return 0.0;
    if (!v->is_number()) {
      Problem(path + key, "must be a number");
      return 0.0;
    }
    const double d = v->get<double>();
    if (!std::isfinite(d)) Problem(path + key, "must be finite");
    return d;
  }
  int Integer(const json& parent, const std::string& key, const std::string& path) {
    const json* v = Find(parent, key, path);
    if (!v) return 0;
    try {
      return io::JsonInteger<int>(*v, path + key);
    } catch (const std::runtime_error&) {
      Problem(path + key, "must be an integer within the range of int");
      return 0;
    }
  }
  bool Bool(const json& parent, const std::string& key, const std::string& path) {
    const json* v = Find(parent, key, path);
    if (!v) return false;
    if (!v->is_boolean()) {
      Problem(path + key, "must be true or false");
      return false;
    }
    return v->get<bool>();
  }
  std::string String(const json& parent, const std::string& key, const std::string& path) {
    const json* v = Find(parent, key, path);
    if (!v) return {};
    if (!v->is_string()) {
      Problem(path + key, "must be a string");
      return {};
    }
    return v->get<std::string>();
  }
  std::vector<double> Numbers(const json& parent, const std::string& key, const std::string& path,
                              std::size_t count) {
    std::vector<double> out(count, 0.0);
    const json* v = Find(parent, key, path);
    if (!v) return out;
    if (!v->is_array() || v->size() != count) {
      Problem(path + key, "must be an array of " + std::to_string(count) + " numbers");
      return out;
    }
    for (std::size_t i = 0; i < count; ++i) {
      if (!(*v)[i].is_number()) {
        Problem(path + key, "must be an array of " + std::to_string(count) + " numbers");
        return out;
      }
      out[i] = (*v)[i].get<double>();
    }
    return out;
  }
  // Reports keys of `object` that are not in `allowed` (typos would otherwise be ignored).
  void NoOtherKeys(const json& object, const std::set<std::string>& allowed,
                   const std::string& path) {
    for (auto it = object.begin(); it != object.end(); ++it) {
      if (!allowed.count(it.key())) Problem(path + it.key(), "unknown key");
    }
  }
  void Problem(const std::string& key, const std::string& what) {
    problems_ << source_ << ": " << key << ": " << what << '\n';
  }
  std::string problems() const { return problems_.str(); }

 private:
  const json* Find(const json& parent, const std::string& key, const std::string& path) {
    const auto it = parent.find(key);
    if (it == parent.end()) {
      Problem(path + key, "missing");
      return nullptr;
    }
    return &*it;
  }
  std::string source_;
  std::ostringstream problems_;
};

json CommandRowToJson(const Eigen::Matrix<double, 1, kCommandsPerWing>& row) {
  json j = json::object();
  for (int i = 0; i < kCommandsPerWing; ++i) j[CommandSuffixes()[i]] = row(i);
  return j;
}

}  // namespace

bool PlantConfig::operator==(const PlantConfig& o) const {
  for (int w = 0; w < kWingCount; ++w) {
    if (hinge_position_m[w] != o.hinge_position_m[w]) return false;
  }
  return name == o.name && mass_kg == o.mass_kg && inertia_kgm2 == o.inertia_kgm2 &&
         gravity_mps2 == o.gravity_mps2 && air_density_kgpm3 == o.air_density_kgpm3 &&
         wing.length_m == o.wing.length_m && wing.root_offset_m == o.wing.root_offset_m &&
         wing.chord_m == o.wing.chord_m && wing.pitch_axis_chords == o.wing.pitch_axis_chords &&
         wing.strip_count == o.wing.strip_count && fore_hind_phase_rad == o.fore_hind_phase_rad &&
         nominal_command == o.nominal_command && limits.min == o.limits.min &&
         limits.max == o.limits.max && integration.sample_rate_hz == o.integration.sample_rate_hz &&
         integration.min_steps_per_beat == o.integration.min_steps_per_beat &&
         integration.rotational_forces == o.integration.rotational_forces &&
         ground.enabled == o.ground.enabled && ground.height_m == o.ground.height_m &&
         divergence.policy == o.divergence.policy &&
         divergence.max_tilt_rad == o.divergence.max_tilt_rad &&
         divergence.max_rate_radps == o.divergence.max_rate_radps &&
         divergence.max_speed_mps == o.divergence.max_speed_mps && sources == o.sources;
}

PlantConfig DefaultPlantConfig() {
  // Literals are written exactly as in config/dimav_40g.json so the two compare equal bit for bit.
  PlantConfig c;
  c.name = "dimav_40g";
  c.mass_kg = 0.04;
  c.inertia_kgm2 = Eigen::Vector3d(0.00011, 8e-05, 0.00019);
  c.gravity_mps2 = 9.81;
  c.air_density_kgpm3 = 1.225;
  c.wing = WingGeometry{0.19, 0.012, 0.055, 0.25, 20};
  c.hinge_position_m = {Eigen::Vector3d(0.03, 0.012, 0.01), Eigen::Vector3d(-0.03, 0.012, 0.01),
                        Eigen::Vector3d(-0.03, -0.012, 0.01), Eigen::Vector3d(0.03, -0.012, 0.01)};
  c.fore_hind_phase_rad = 3.141592653589793;
  c.nominal_command << 0.0, 5.4, 1.0471975511965976, 1.5707963267948966, 0.7853981633974483, 0.0;
  c.limits.min << -0.5235987755982988, 0.0, 0.0, 0.7853981633974483, 0.0, -3.141592653589793;
  c.limits.max << 0.5235987755982988, 8.0, 1.4835298641951802, 2.356194490192345,
      1.0471975511965976, 3.141592653589793;
  c.integration = IntegrationSettings{100.0, 50, true};
  c.ground = GroundSettings{true, 0.0};
  c.divergence = DivergenceSettings{DivergencePolicy::kStop, 1.3962634015954636, 60.0, 30.0};
  c.sources = {
      {"mass_kg", "docs/plant.md 40 g parameter set (Kok & Chahl's vehicle mass, paper section I)"},
      {"inertia",
       "docs/plant.md: self-consistent substitute for Kok & Chahl's unpublished geometry"},
      {"gravity_mps2", "standard gravity, rounded"},
      {"air_density_kgpm3", "ISA sea level"},
      {"wing",
       "docs/plant.md (rectangular 0.19 m x 0.055 m wing, root 0.012 m out from the stroke axis: "
       "this "
       "reading reproduces docs/plant.md's 5.36 Hz translational hover; x0 = 0.25 chord, Sane & "
       "Dickinson 2002); strips: docs/plant.md asks 20-40"},
      {"hinges_m", "docs/plant.md hinge table"},
      {"fore_hind_phase_rad", "Wang & Russell 2007: counter-stroking (pi) to hover"},
      {"nominal_command",
       "docs/plant.md nominal kinematics (phi0 60 deg, beta 0, theta_m 90 deg, theta0 45 deg); "
       "freq_hz is only the trim finder's initial guess"},
      {"limits",
       "odonata choice: mechanically plausible ranges; freq max 8 Hz sets the RK4 step (>= 50 "
       "steps per beat)"},
      {"integration",
       "docs/plant.md: fixed-step RK4 >= 50 steps per wing beat, 100 Hz samples (paper section "
       "IV)"},
      {"ground", "odonata choice: flat ground at z = 0, inelastic sticking contact"},
      {"divergence",
       "odonata choice: tumbling past 80 deg, 60 rad/s or 30 m/s is treated as divergence"},
  };
  return c;
}

PlantConfig ParsePlantConfig(const std::string& json_text, const std::string& source_name) {
  json root;
  try {
    root = json::parse(json_text);
  } catch (const json::parse_error& e) {
    throw PlantConfigError(source_name + ": not valid JSON: " + e.what());
  }
  if (!root.is_object()) throw PlantConfigError(source_name + ": top level must be an object");

  Reader r(source_name);
  PlantConfig c;
  r.NoOtherKeys(root,
                {"name", "mass_kg", "inertia_xx_kgm2", "inertia_yy_kgm2", "inertia_zz_kgm2",
                 "gravity_mps2", "air_density_kgpm3", "wing", "hinges_m", "fore_hind_phase_rad",
                 "nominal_command", "limits", "integration", "ground", "divergence", "sources"},
                "");
  c.name = r.String(root, "name", "");
  c.mass_kg = r.Number(root, "mass_kg", "");
  c.inertia_kgm2 =
      Eigen::Vector3d(r.Number(root, "inertia_xx_kgm2", ""), r.Number(root, "inertia_yy_kgm2", ""),
                      r.Number(root, "inertia_zz_kgm2", ""));
  c.gravity_mps2 = r.Number(root, "gravity_mps2", "");
  c.air_density_kgpm3 = r.Number(root, "air_density_kgpm3", "");
  c.fore_hind_phase_rad = r.Number(root, "fore_hind_phase_rad", "");

  if (const json* wing = r.Object(root, "wing", "")) {
    r.NoOtherKeys(*wing, {"length_m", "root_offset_m", "chord_m", "pitch_axis_chords", "strips"},
                  "wing.");
    c.wing.length_m = r.Number(*wing, "length_m", "wing.");
    c.wing.root_offset_m = r.Number(*wing, "root_offset_m", "wing.");
    c.wing.chord_m = r.Number(*wing, "chord_m", "wing.");
    c.wing.pitch_axis_chords = r.Number(*wing, "pitch_axis_chords", "wing.");
    c.wing.strip_count = r.Integer(*wing, "strips", "wing.");
  }
  if (const json* hinges = r.Object(root, "hinges_m", "")) {
    r.NoOtherKeys(*hinges, {kHingeKeys.begin(), kHingeKeys.end()}, "hinges_m.");
    for (int w = 0; w < kWingCount; ++w) {
      const std::vector<double> p = r.Numbers(*hinges, kHingeKeys[w], "hinges_m.", 3);
      c.hinge_position_m[w] = Eigen::Vector3d(p[0], p[1], p[2]);
    }
  }
  const std::set<std::string> command_keys(CommandSuffixes().begin(), CommandSuffixes().end());
  if (const json* nominal = r.Object(root, "nominal_command", "")) {
    r.NoOtherKeys(*nominal, command_keys, "nominal_command.");
    for (int i = 0; i < kCommandsPerWing; ++i) {
      c.nominal_command(i) = r.Number(*nominal, CommandSuffixes()[i], "nominal_command.");
    }
  }
  if (const json* limits = r.Object(root, "limits", "")) {
    r.NoOtherKeys(*limits, command_keys, "limits.");
    for (int i = 0; i < kCommandsPerWing; ++i) {
      const std::vector<double> range = r.Numbers(*limits, CommandSuffixes()[i], "limits.", 2);
      c.limits.min(i) = range[0];
      c.limits.max(i) = range[1];
    }
  }
  if (const json* integ = r.Object(root, "integration", "")) {
    r.NoOtherKeys(*integ, {"sample_rate_hz", "min_steps_per_beat", "rotational_forces"},
                  "integration.");
    c.integration.sample_rate_hz = r.Number(*integ, "sample_rate_hz", "integration.");
    c.integration.min_steps_per_beat = r.Integer(*integ, "min_steps_per_beat", "integration.");
    c.integration.rotational_forces = r.Bool(*integ, "rotational_forces", "integration.");
  }
  if (const json* ground = r.Object(root, "ground", "")) {
    r.NoOtherKeys(*ground, {"enabled", "height_m"}, "ground.");
    c.ground.enabled = r.Bool(*ground, "enabled", "ground.");
    c.ground.height_m = r.Number(*ground, "height_m", "ground.");
  }
  if (const json* div = r.Object(root, "divergence", "")) {
    r.NoOtherKeys(*div, {"policy", "max_tilt_rad", "max_rate_radps", "max_speed_mps"},
                  "divergence.");
    const std::string policy = r.String(*div, "policy", "divergence.");
    if (policy == "stop") {
      c.divergence.policy = DivergencePolicy::kStop;
    } else if (policy == "reset") {
      c.divergence.policy = DivergencePolicy::kReset;
    } else if (div->contains("policy")) {
      r.Problem("divergence.policy", "must be \"stop\" or \"reset\", not \"" + policy + "\"");
    }
    c.divergence.max_tilt_rad = r.Number(*div, "max_tilt_rad", "divergence.");
    c.divergence.max_rate_radps = r.Number(*div, "max_rate_radps", "divergence.");
    c.divergence.max_speed_mps = r.Number(*div, "max_speed_mps", "divergence.");
  }
  if (const json* sources = r.Object(root, "sources", "")) {
    for (auto it = sources->begin(); it != sources->end(); ++it) {
      if (!it.value().is_string()) {
        r.Problem("sources." + it.key(), "must be a string");
      } else {
        c.sources[it.key()] = it.value().get<std::string>();
      }
    }
    for (const char* key : kSourceKeys) {
      if (!sources->contains(key)) r.Problem(std::string("sources.") + key, "missing");
    }
  }

  std::string problems = r.problems();
  if (problems.empty()) {
    // Physical checks only make sense once the structure is complete.
    std::istringstream lines(ValidatePlantConfig(c));
    for (std::string line; std::getline(lines, line);) problems += source_name + ": " + line + '\n';
  }
  if (!problems.empty()) throw PlantConfigError(problems);
  return c;
}

PlantConfig LoadPlantConfig(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw PlantConfigError(path + ": cannot open plant configuration");
  std::ostringstream text;
  text << in.rdbuf();
  return ParsePlantConfig(text.str(), path);
}

std::string ValidatePlantConfig(const PlantConfig& c) {
  std::ostringstream p;
  auto positive = [&p](double v, const char* key) {
    if (!(v > 0.0) || !std::isfinite(v))
      p << key << ": must be positive and finite, got " << v << '\n';
  };
  positive(c.mass_kg, "mass_kg");
  positive(c.inertia_kgm2.x(), "inertia_xx_kgm2");
  positive(c.inertia_kgm2.y(), "inertia_yy_kgm2");
  positive(c.inertia_kgm2.z(), "inertia_zz_kgm2");
  const Eigen::Vector3d& j = c.inertia_kgm2;
  if (j.x() + j.y() < j.z() || j.y() + j.z() < j.x() || j.x() + j.z() < j.y()) {
    p << "inertia: principal moments violate the triangle inequality (not a physical body)\n";
  }
  if (!(c.gravity_mps2 >= 0.0)) p << "gravity_mps2: must be >= 0\n";
  positive(c.air_density_kgpm3, "air_density_kgpm3");
  positive(c.wing.length_m, "wing.length_m");
  positive(c.wing.chord_m, "wing.chord_m");
  if (!(c.wing.root_offset_m >= 0.0)) p << "wing.root_offset_m: must be >= 0\n";
  if (!(c.wing.pitch_axis_chords >= 0.0 && c.wing.pitch_axis_chords <= 1.0)) {
    p << "wing.pitch_axis_chords: must be in [0, 1]\n";
  }
  if (c.wing.strip_count < 1 || c.wing.strip_count > 1000) p << "wing.strips: must be 1..1000\n";
  for (int w = 0; w < kWingCount; ++w) {
    if (!c.hinge_position_m[w].allFinite()) p << "hinges_m." << kHingeKeys[w] << ": not finite\n";
  }
  for (int i = 0; i < kCommandsPerWing; ++i) {
    const std::string& key = CommandSuffixes()[i];
    if (!(c.limits.min(i) <= c.limits.max(i))) p << "limits." << key << ": min > max\n";
    if (!(c.nominal_command(i) >= c.limits.min(i) && c.nominal_command(i) <= c.limits.max(i))) {
      p << "nominal_command." << key << ": outside limits." << key << '\n';
    }
  }
  if (!(c.limits.max(kFlapFrequency) > 0.0)) p << "limits.freq_hz: max must be > 0\n";
  if (c.limits.min(kFlapFrequency) < 0.0) p << "limits.freq_hz: min must be >= 0\n";
  if (c.limits.min(kStrokeAmplitude) < 0.0) p << "limits.amp_rad: min must be >= 0\n";
  positive(c.integration.sample_rate_hz, "integration.sample_rate_hz");
  if (c.integration.min_steps_per_beat < 4) {
    p << "integration.min_steps_per_beat: must be >= 4 (docs/plant.md asks >= 50)\n";
  }
  positive(c.divergence.max_tilt_rad, "divergence.max_tilt_rad");
  positive(c.divergence.max_rate_radps, "divergence.max_rate_radps");
  positive(c.divergence.max_speed_mps, "divergence.max_speed_mps");
  return p.str();
}

std::string PlantConfigToJson(const PlantConfig& c) {
  json j;
  j["name"] = c.name;
  j["mass_kg"] = c.mass_kg;
  j["inertia_xx_kgm2"] = c.inertia_kgm2.x();
  j["inertia_yy_kgm2"] = c.inertia_kgm2.y();
  j["inertia_zz_kgm2"] = c.inertia_kgm2.z();
  j["gravity_mps2"] = c.gravity_mps2;
  j["air_density_kgpm3"] = c.air_density_kgpm3;
  j["wing"] = {{"length_m", c.wing.length_m},
               {"root_offset_m", c.wing.root_offset_m},
               {"chord_m", c.wing.chord_m},
               {"pitch_axis_chords", c.wing.pitch_axis_chords},
               {"strips", c.wing.strip_count}};
  for (int w = 0; w < kWingCount; ++w) {
    const Eigen::Vector3d& h = c.hinge_position_m[w];
    j["hinges_m"][kHingeKeys[w]] = {h.x(), h.y(), h.z()};
  }
  j["fore_hind_phase_rad"] = c.fore_hind_phase_rad;
  j["nominal_command"] = CommandRowToJson(c.nominal_command);
  for (int i = 0; i < kCommandsPerWing; ++i) {
    j["limits"][CommandSuffixes()[i]] = {c.limits.min(i), c.limits.max(i)};
  }
  j["integration"] = {{"sample_rate_hz", c.integration.sample_rate_hz},
                      {"min_steps_per_beat", c.integration.min_steps_per_beat},
                      {"rotational_forces", c.integration.rotational_forces}};
  j["ground"] = {{"enabled", c.ground.enabled}, {"height_m", c.ground.height_m}};
  j["divergence"] = {{"policy", c.divergence.policy == DivergencePolicy::kStop ? "stop" : "reset"},
                     {"max_tilt_rad", c.divergence.max_tilt_rad},
                     {"max_rate_radps", c.divergence.max_rate_radps},
                     {"max_speed_mps", c.divergence.max_speed_mps}};
  j["sources"] = c.sources;
  return j.dump(2) + "\n";
}

int StepsPerSample(const PlantConfig& c) {
  const double steps = std::ceil(c.integration.min_steps_per_beat * c.limits.max(kFlapFrequency) /
                                     c.integration.sample_rate_hz -
                                 1e-9);
  return steps < 1.0 ? 1 : static_cast<int>(steps);
}

}  // namespace odonata::plant

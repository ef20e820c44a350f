#include "plant/plant_config.hpp"

#include <gtest/gtest.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

namespace odonata::plant {
namespace {

std::string ReadFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

const std::string kDefaultPath = std::string(ODONATA_PLANT_CONFIG_DIR) + "/dimav_40g.json";

TEST(PlantConfig, CompiledDefaultsEqualTheJsonFile) {
  EXPECT_TRUE(LoadPlantConfig(kDefaultPath) == DefaultPlantConfig());
}

TEST(PlantConfig, DefaultsAreValidAndRoundTrip) {
  const PlantConfig c = DefaultPlantConfig();
  EXPECT_EQ(ValidatePlantConfig(c), "");
  EXPECT_TRUE(ParsePlantConfig(PlantConfigToJson(c), "round trip") == c);
}

TEST(PlantConfig, EveryParameterGroupHasASource) {
  const PlantConfig c = DefaultPlantConfig();
  for (const char* key : {"mass_kg", "inertia", "wing", "hinges_m", "limits", "integration"}) {
    ASSERT_TRUE(c.sources.count(key)) << key;
    EXPECT_FALSE(c.sources.at(key).empty()) << key;
  }
}

TEST(PlantConfig, ReportsEveryProblemAtOnce) {
  nlohmann::json j = nlohmann::json::parse(ReadFile(kDefaultPath));
  j.erase("mass_kg");
  j["wing"]["chord_mm"] = 55;                   // typo: unknown key
  j["divergence"]["policy"] = "explode";        // bad enum
  j["integration"]["sample_rate_hz"] = "fast";  // wrong type
  try {
    ParsePlantConfig(j.dump(), "bad.json");
    FAIL() << "expected PlantConfigError";
  } catch (const PlantConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("bad.json: mass_kg: missing"), std::string::npos) << what;
    EXPECT_NE(what.find("wing.chord_mm: unknown key"), std::string::npos) << what;
    EXPECT_NE(what.find("divergence.policy"), std::string::npos) << what;
    EXPECT_NE(what.find("integration.sample_rate_hz: must be a number"), std::string::npos) << what;
  }
}

TEST(PlantConfig, RejectsPhysicallyInvalidValues) {
  nlohmann::json j = nlohmann::json::parse(ReadFile(kDefaultPath));
  j["mass_kg"] = -1.0;
  j["limits"]["freq_hz"] = {8.0, 1.0};
  try {
    ParsePlantConfig(j.dump(), "phys.json");
    FAIL() << "expected PlantConfigError";
  } catch (const PlantConfigError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("mass_kg: must be positive"), std::string::npos) << what;
    EXPECT_NE(what.find("limits.freq_hz: min > max"), std::string::npos) << what;
  }
}

TEST(PlantConfig, UnreadableOrInvalidFilesThrow) {
  EXPECT_THROW(LoadPlantConfig("/nonexistent/plant.json"), PlantConfigError);
  EXPECT_THROW(ParsePlantConfig("{ not json", "x"), PlantConfigError);
}

TEST(PlantConfig, DefaultStepGivesAtLeastFiftyStepsPerBeatAtMaxFrequency) {
  const PlantConfig c = DefaultPlantConfig();
  const int steps = StepsPerSample(c);
  EXPECT_EQ(steps, 4);  // 2.5 ms
  const double steps_per_beat = c.integration.sample_rate_hz * steps / c.limits.max(kFlapFrequency);
  EXPECT_GE(steps_per_beat, 50.0);
}

}  // namespace
}  // namespace odonata::plant

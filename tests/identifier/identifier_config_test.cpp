// odonata-identifier's configuration file: every problem reported at once, by name, and no value
// silently converted or ignored.
#include "identifier_config/identifier_config.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <functional>
#include <stdexcept>
#include <string>

#include <nlohmann/json.hpp>

namespace odonata::identifier {
namespace {

// Writes the example configuration with `edit` applied and loads it; returns the error text, or
// "" when it loaded.
std::string LoadEdited(const std::function<void(nlohmann::json&)>& edit) {
  nlohmann::json j = nlohmann::json::parse(ExampleIdentifierConfig());
  edit(j);
  char path[] = "/tmp/odonata_identifier_config_XXXXXX";
  const int fd = mkstemp(path);
  EXPECT_GE(fd, 0);
  close(fd);
  std::ofstream(path) << j.dump();
  std::string error;
  try {
    LoadIdentifierConfig(path);
  } catch (const std::runtime_error& e) {
    error = e.what();
  }
  std::remove(path);
  return error;
}

TEST(IdentifierConfig, TheWriterWritesEveryKeyTheReaderReads) {
  // Every field away from its default: what is written reads back the same, key by key.
  IdentifierConfig c = DefaultIdentifierConfig();
  c.instance = "id-2";
  c.source = SampleSource::kSignals;
  c.spec.outputs = {"vz", "roll"};
  c.spec.inputs = {"thrust"};
  c.spec.output_lags = 3;
  c.spec.input_lags = 2;
  c.spec.delay = 0;
  c.model.consequent = fuzzy::ConsequentKind::kSingleton;
  c.model.entropy.threshold = 0.123;
  c.model.entropy.max_rules = 7;
  c.model.entropy.kappa = 1.7;
  c.model.entropy.sigma_init = 0.4;
  c.model.entropy.sigma_min = 0.05;
  c.model.entropy.sigma_max = 1.5;
  c.model.entropy.prune_utility = 0.01;
  c.model.entropy.prune_min_age = 77;
  c.model.forgetting = 0.995;
  c.ranges = {{"vz", {-1.5, 2.5}}, {"roll", {-0.4, 0.4}}, {"thrust", {0.0, 1.0}}};
  c.snapshot_period_s = 0.25;
  c.snapshot_every_samples = 9;
  c.resume_wait_s = 4.5;
  c.decimate = 5;
  c.max_gap = 2;
  c.refit.first = 300;
  c.refit.every = 900;
  c.refit.buffer = 5000;
  c.refit.history = 0.25;
  c.refit.at_freeze = false;
  c.refit.threads = 2;
  c.refit.horizon = 20;
  c.channels.signals = "MY_SIGNALS";
  c.channels.prediction = "MY_PREDICTIONS";
  const nlohmann::ordered_json written = IdentifierConfigToJson(c);
  const IdentifierConfig r = ParseIdentifierConfig(written.dump(), "written");
  EXPECT_EQ(IdentifierConfigToJson(r), written);
  EXPECT_EQ(r.instance, "id-2");
  EXPECT_EQ(r.source, SampleSource::kSignals);
  EXPECT_EQ(r.spec.outputs, c.spec.outputs);
  EXPECT_EQ(r.spec.delay, 0);
  EXPECT_EQ(r.model.consequent, fuzzy::ConsequentKind::kSingleton);
  EXPECT_EQ(r.model.entropy.prune_min_age, 77);
  EXPECT_EQ(r.model.forgetting, 0.995);
  EXPECT_EQ(r.ranges, c.ranges);
  EXPECT_EQ(r.snapshot_every_samples, 9);
  EXPECT_EQ(r.decimate, 5);
  EXPECT_EQ(r.refit.history, 0.25);
  EXPECT_FALSE(r.refit.at_freeze);
  EXPECT_EQ(r.refit.horizon, 20);
  EXPECT_EQ(r.channels.signals, "MY_SIGNALS");
  EXPECT_EQ(r.channels.prediction, "MY_PREDICTIONS");
  EXPECT_EQ(r.channels.command, bus::ChannelConfig{}.command);
}

TEST(IdentifierConfig, TheExampleLoads) {
  EXPECT_EQ(LoadEdited([](nlohmann::json&) {}), "");
}

TEST(IdentifierConfig, AnUnknownKeyIsAnErrorNamingIt) {
  const std::string e = LoadEdited([](nlohmann::json& j) { j["entropy_treshold"] = 0.2; });
  EXPECT_NE(e.find("unknown key \"entropy_treshold\""), std::string::npos) << e;
  // A typo gets the key it was meant to be (issue 48's first-hour papercuts); a stranger does not.
  EXPECT_NE(e.find("did you mean \"entropy_threshold\"?"), std::string::npos) << e;
  const std::string swapped = LoadEdited([](nlohmann::json& j) { j["refit_horzion"] = 50; });
  EXPECT_NE(swapped.find("did you mean \"refit_horizon\"?"), std::string::npos) << swapped;
  const std::string stranger = LoadEdited([](nlohmann::json& j) { j["colour"] = "blue"; });
  EXPECT_NE(stranger.find("unknown key \"colour\""), std::string::npos) << stranger;
  EXPECT_EQ(stranger.find("did you mean"), std::string::npos) << stranger;
}

TEST(IdentifierConfig, IntegersAreNeverSilentlyConverted) {
  for (const nlohmann::json& bad : {nlohmann::json(1.3e29), nlohmann::json(4294967297LL),
                                    nlohmann::json(1.5), nlohmann::json(-1), nlohmann::json("1")}) {
    const std::string e = LoadEdited([&bad](nlohmann::json& j) { j["delay"] = bad; });
    EXPECT_NE(e.find("delay"), std::string::npos) << bad.dump() << ": " << e;
  }
  const std::string lags = LoadEdited([](nlohmann::json& j) {
    j["ny"] = 2147483647;
    j["max_rules"] = 1e12;
  });
  EXPECT_NE(lags.find("\"ny\" must be in [0, 1000]"), std::string::npos) << lags;
  EXPECT_NE(lags.find("max_rules"), std::string::npos) << lags;
}

TEST(IdentifierConfig, DecimationIsAWholeFactorOfAtLeastOne) {
  for (const nlohmann::json& bad : {nlohmann::json(0), nlohmann::json(2.5), nlohmann::json(-5)}) {
    const std::string e = LoadEdited([&bad](nlohmann::json& j) { j["decimate"] = bad; });
    EXPECT_NE(e.find("decimate"), std::string::npos) << bad.dump() << ": " << e;
  }
  EXPECT_EQ(LoadEdited([](nlohmann::json& j) { j["decimate"] = 5; }), "");
  EXPECT_EQ(ParseIdentifierConfig(ExampleIdentifierConfig(), "example").decimate, 1);
}

TEST(IdentifierConfig, RefitHistoryIsAShareOfTheBuffer) {
  for (const nlohmann::json& bad :
       {nlohmann::json(-0.1), nlohmann::json(1.5), nlohmann::json("x"), nlohmann::json(nullptr)}) {
    const std::string e = LoadEdited([&bad](nlohmann::json& j) { j["refit_history"] = bad; });
    EXPECT_NE(e.find("\"refit_history\" must be a number in [0, 1]"), std::string::npos)
        << bad.dump() << ": " << e;
  }
  EXPECT_EQ(LoadEdited([](nlohmann::json& j) { j["refit_history"] = 0; }), "");
  EXPECT_EQ(ParseIdentifierConfig(ExampleIdentifierConfig(), "example").refit.history, 0.5);
}

TEST(IdentifierConfig, RefitHorizonIsFreeRunOrAtLeastTwoStepsAhead) {
  for (const nlohmann::json& bad :
       {nlohmann::json(-1), nlohmann::json(2.5), nlohmann::json("50")}) {
    const std::string e = LoadEdited([&bad](nlohmann::json& j) { j["refit_horizon"] = bad; });
    EXPECT_NE(e.find("refit_horizon"), std::string::npos) << bad.dump() << ": " << e;
  }
  // One step ahead is not a horizon: odonata-fit --horizon refuses it too.
  const std::string one = LoadEdited([](nlohmann::json& j) { j["refit_horizon"] = 1; });
  EXPECT_NE(one.find("\"refit_horizon\" must be 0 (refits choose in free run) or K >= 2"),
            std::string::npos)
      << one;
  EXPECT_EQ(ParseIdentifierConfig(ExampleIdentifierConfig(), "example").refit.horizon, 0);
  nlohmann::json j = nlohmann::json::parse(ExampleIdentifierConfig());
  j["refit_horizon"] = 50;
  EXPECT_EQ(ParseIdentifierConfig(j.dump(), "edited").refit.horizon, 50);
}

// The documented default (issue 61): a configuration without the key, and the one odonata-fit
// --save-config writes, snapshot every 100 learned samples.
TEST(IdentifierConfig, SnapshotsEveryHundredSamplesByDefault) {
  EXPECT_EQ(IdentifierConfig{}.snapshot_every_samples, 100);
  nlohmann::ordered_json j = IdentifierConfigToJson(DefaultIdentifierConfig());
  EXPECT_EQ(j["snapshot_every_samples"], 100);
  j.erase("snapshot_every_samples");
  EXPECT_EQ(ParseIdentifierConfig(j.dump(), "no key").snapshot_every_samples, 100);
}

}  // namespace
}  // namespace odonata::identifier

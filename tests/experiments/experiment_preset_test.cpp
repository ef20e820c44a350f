#include "experiments/experiment_preset.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>

namespace odonata::experiments {
namespace {

// docs/identifier.md §10.
const std::map<std::string, double> kPaperEntropy = {
    {"actuator_fz", 0.007}, {"actuator_fx", 0.002}, {"vertical_velocity", 0.05},
    {"roll", 0.01},         {"pitch", 0.001},       {"yaw", 0.25}};
const std::map<std::string, int> kPaperMfs = {
    {"actuator_fz", 18}, {"actuator_fx", 8}, {"vertical_velocity", 41},
    {"roll", 6},         {"pitch", 3},       {"yaw", 34}};

TEST(Presets, AreTheSixPaperExperimentsWithIdentificationMetadata) {
  ASSERT_EQ(Presets().size(), 6u);
  for (const ExperimentPreset& p : Presets()) {
    SCOPED_TRACE(p.name);
    EXPECT_EQ(FindPreset(p.name), &p);
    EXPECT_DOUBLE_EQ(p.entropy_threshold, kPaperEntropy.at(p.name));
    EXPECT_EQ(p.paper_mf_count, kPaperMfs.at(p.name));
    EXPECT_FALSE(p.output_column.empty());
    EXPECT_FALSE(p.input_columns.empty());
    EXPECT_FALSE(p.paper_accuracy_text.empty());
    EXPECT_GE(p.ny, 1);
    EXPECT_GE(p.nu, 1);
    EXPECT_GE(p.delay, 0);
    EXPECT_GT(p.train_duration_s, 0.0);
    EXPECT_GT(p.validate_duration_s, 0.0);
  }
  EXPECT_EQ(FindPreset("nope"), nullptr);
}

class EveryPreset : public ::testing::TestWithParam<std::string> {};

TEST_P(EveryPreset, TrainAndValidateDifferStayWithinLimitsAndAreSeeded) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  const ExperimentPreset& p = *FindPreset(GetParam());
  const ExperimentRun train = BuildExperimentRun(p, Phase::kTrain, 11, 0.0, config);
  const ExperimentRun val = BuildExperimentRun(p, Phase::kValidate, 11, 0.0, config);
  const ExperimentRun again = BuildExperimentRun(p, Phase::kTrain, 11, 0.0, config);
  EXPECT_EQ(train.commands.size(), static_cast<std::size_t>(p.train_duration_s * 100 + 0.5));
  EXPECT_EQ(val.commands.size(), static_cast<std::size_t>(p.validate_duration_s * 100 + 0.5));

  // Same seed ⇒ bit-identical; train ≠ validate.
  ASSERT_EQ(train.commands.size(), again.commands.size());
  double max_diff = 0.0;
  for (std::size_t k = 0; k < train.commands.size(); ++k) {
    ASSERT_TRUE(train.commands[k] == again.commands[k]);
    if (k < val.commands.size()) {
      max_diff = std::max(max_diff, (train.commands[k] - val.commands[k]).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_GT(max_diff, 1e-3);
  EXPECT_EQ(train.excitation_values, again.excitation_values);

  // Designed within the actuator limits (the builder's clamp never had to act), and excited
  // (not constant).
  for (const ExperimentRun* run : {&train, &val}) {
    EXPECT_EQ(run->clamped_samples, 0u) << "of " << run->commands.size() << " samples";
    double spread = 0.0;
    for (const plant::CommandMatrix& c : run->commands) {
      for (int w = 0; w < plant::kWingCount; ++w) {
        ASSERT_TRUE((c.row(w).array() >= config.limits.min.array()).all());
        ASSERT_TRUE((c.row(w).array() <= config.limits.max.array()).all());
      }
      spread = std::max(spread, (c - run->commands.front()).cwiseAbs().maxCoeff());
    }
    EXPECT_GT(spread, 0.01);
  }

  // Input columns exist: either a command column or an excitation column of the run.
  for (const std::string& in : p.input_columns) {
    const bool is_command = in.rfind("w1_", 0) == 0;
    bool is_excitation = false;
    for (const std::string& name : train.excitation_names) is_excitation |= name == in;
    EXPECT_TRUE(is_command || is_excitation) << in;
  }

  if (!p.clamped_body) {
    // Free flight starts at hover trim, in the air.
    EXPECT_NEAR(train.initial.state.position_m.z(), 50.0, 1e-12);
    EXPECT_TRUE(train.initial.prior_command == train.trim.command);
    // Attitude excitations are zero-mean.
    if (p.name != "vertical_velocity") {
      const std::vector<double>& u = train.excitation_values.at(0);
      double sum = 0.0, sum_abs = 0.0;
      for (const double x : u) {
        sum += x;
        sum_abs += std::fabs(x);
      }
      EXPECT_LT(std::fabs(sum), 0.05 * sum_abs);  // partial slow first cycles
      EXPECT_EQ(u.front(), 0.0);                  // faded in
    }
  }
}

TEST_P(EveryPreset, SeedChangesTheRun) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  const ExperimentPreset& p = *FindPreset(GetParam());
  const ExperimentRun a = BuildExperimentRun(p, Phase::kTrain, 1, 5.0, config);
  const ExperimentRun b = BuildExperimentRun(p, Phase::kTrain, 2, 5.0, config);
  bool differ = false;
  for (std::size_t k = 0; k < a.commands.size() && !differ; ++k) {
    differ = !(a.commands[k] == b.commands[k]);
  }
  EXPECT_TRUE(differ);
  EXPECT_EQ(a.commands.size(), 500u);
}

INSTANTIATE_TEST_SUITE_P(Paper, EveryPreset,
                         ::testing::Values("actuator_fz", "actuator_fx", "vertical_velocity",
                                           "roll", "pitch", "yaw"));

}  // namespace
}  // namespace odonata::experiments

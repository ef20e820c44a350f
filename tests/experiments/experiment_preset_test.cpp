#include "experiments/experiment_preset.hpp"

#include <gtest/gtest.h>

#include <algorithm>
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

std::string BaseName(const ExperimentPreset& p) {
  return p.held_vehicle ? p.name.substr(0, p.name.size() - 5) : p.name;
}

TEST(Presets, AreTheSixPaperExperimentsWithIdentificationMetadata) {
  ASSERT_EQ(Presets().size(), 13u);
  for (std::size_t i = 0; i < 6; ++i) EXPECT_FALSE(Presets()[i].held_vehicle);
  for (const ExperimentPreset& p : Presets()) {
    SCOPED_TRACE(p.name);
    if (p.beyond_paper) continue;
    EXPECT_EQ(p.decimate, 1);
    EXPECT_EQ(FindPreset(p.name), &p);
    EXPECT_DOUBLE_EQ(p.entropy_threshold, kPaperEntropy.at(BaseName(p)));
    EXPECT_EQ(p.paper_mf_count, kPaperMfs.at(BaseName(p)));
    EXPECT_FALSE(p.output_column.empty());
    EXPECT_FALSE(p.input_columns.empty());
    EXPECT_FALSE(p.paper_accuracy_text.empty());
    EXPECT_GE(p.ny, 1);
    EXPECT_GE(p.nu, 1);
    EXPECT_GE(p.delay, 0);
    EXPECT_GT(p.train_duration_s, 0.0);
    EXPECT_GT(p.validate_duration_s, 0.0);
    EXPECT_GT(p.select_duration_s, 0.0);
    EXPECT_FALSE(p.select_excitation.empty());
    EXPECT_NE(p.select_excitation, p.train_excitation);
    EXPECT_NE(p.select_excitation, p.validate_excitation);
  }
  EXPECT_EQ(FindPreset("nope"), nullptr);
}

// Free flight identifies the open-loop vehicle from the command actually applied (hold
// included); a preset that identifies the held vehicle says so in its name and description.
TEST(Presets, FreeFlightInputsAreTheAppliedCommandUnlessNamedHeld) {
  for (const ExperimentPreset& p : Presets()) {
    SCOPED_TRACE(p.name);
    const bool named_held = p.name.size() > 5 && p.name.substr(p.name.size() - 5) == "_held";
    EXPECT_EQ(p.held_vehicle, named_held);
    if (p.clamped_body || p.beyond_paper) continue;
    ASSERT_EQ(p.input_columns.size(), 1u);
    const std::string& in = p.input_columns.front();
    if (p.held_vehicle) {
      EXPECT_EQ(in, "u_" + BaseName(p) + "_rad");
      EXPECT_NE(p.description.find("HELD VEHICLE"), std::string::npos);
      EXPECT_TRUE(p.attitude_hold);
    } else {
      EXPECT_NE(in.find("_applied_rad"), std::string::npos) << in;
      const auto& names = vehicle::AppliedChannelNames();
      EXPECT_NE(std::find(names.begin(), names.end(), in), names.end()) << in;
    }
  }
  for (const char* held : {"roll_held", "pitch_held"}) EXPECT_NE(FindPreset(held), nullptr);
}

TEST(Phases, HaveNamesAndParse) {
  EXPECT_EQ(PhaseNames(), (std::vector<std::string>{"train", "select", "validate"}));
  for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
    EXPECT_EQ(ParsePhase(PhaseName(phase)), phase);
  }
  EXPECT_FALSE(ParsePhase("test").has_value());
  EXPECT_FALSE(ParsePhase("").has_value());
}

// The channel readers see the designed mappings, and only their own channel: the hold's roll
// and pitch corrections (vehicle::ApplyAttitudeHold) leave the vertical and yaw channels alone and
// show up in full in the roll and pitch ones.
TEST(CommandChannels, ReadTheActuatorMappingsAndTheHold) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  const plant::TrimResult trim = plant::FindHoverTrim(config);
  plant::CommandMatrix c = trim.command;
  const std::vector<double> at_trim = vehicle::AppliedChannelValues(c, trim.amp_rad);
  for (const double v : at_trim) EXPECT_EQ(v, 0.0);
  c(0, plant::kStrokeAmplitude) += 0.03;  // fore-left
  c(1, plant::kStrokeAmplitude) += 0.01;  // hind-left
  c(2, plant::kStrokeAmplitude) -= 0.02;  // hind-right
  c(3, plant::kStrokeAmplitude) += 0.00;  // fore-right
  c(2, plant::kStrokePlaneAngle) = 0.2;
  c(3, plant::kStrokePlaneAngle) = 0.1;
  c(0, plant::kStrokePlaneAngle) = -0.1;
  EXPECT_NEAR(vehicle::VerticalChannelRad(c, trim.amp_rad), (0.03 + 0.01 - 0.02) / 4, 1e-14);
  EXPECT_NEAR(vehicle::RollChannelRad(c), 0.5 * ((0.03 + 0.01) / 2 - (-0.02) / 2), 1e-14);
  EXPECT_NEAR(vehicle::PitchChannelRad(c), 0.5 * ((0.03 + 0.0) / 2 - (0.01 - 0.02) / 2), 1e-14);
  EXPECT_NEAR(vehicle::YawChannelRad(c), 0.5 * ((0.2 + 0.1) / 2 - (-0.1) / 2), 1e-14);

  plant::PlantOutput o;
  o.roll_rad = 0.1;
  o.pitch_rad = -0.05;
  o.rate_body_radps = Eigen::Vector3d(0.3, 0.2, 0.0);
  const vehicle::AttitudeHoldGains g = vehicle::DefaultAttitudeHoldGains();
  const plant::CommandMatrix held = vehicle::ApplyAttitudeHold(g, c, o);
  EXPECT_NEAR(vehicle::VerticalChannelRad(held, trim.amp_rad),
              vehicle::VerticalChannelRad(c, trim.amp_rad), 1e-14);
  EXPECT_EQ(vehicle::YawChannelRad(held), vehicle::YawChannelRad(c));
  EXPECT_NEAR(vehicle::RollChannelRad(held) - vehicle::RollChannelRad(c),
              -(g.roll_kp * 0.1 + g.roll_kd_s * 0.3), 1e-14);
  EXPECT_NEAR(vehicle::PitchChannelRad(held) - vehicle::PitchChannelRad(c),
              g.pitch_kp * -0.05 + g.pitch_kd_s * 0.2, 1e-14);
}

class EveryPreset : public ::testing::TestWithParam<std::string> {};

// Largest command difference between two runs over their common length.
double MaxDifference(const ExperimentRun& a, const ExperimentRun& b) {
  double max_diff = 0.0;
  for (std::size_t k = 0; k < std::min(a.commands.size(), b.commands.size()); ++k) {
    max_diff = std::max(max_diff, (a.commands[k] - b.commands[k]).cwiseAbs().maxCoeff());
  }
  return max_diff;
}

TEST_P(EveryPreset, TrainSelectAndValidateDifferStayWithinLimitsAndAreSeeded) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  const ExperimentPreset& p = *FindPreset(GetParam());
  const ExperimentRun train = BuildExperimentRun(p, Phase::kTrain, 11, 0.0, config);
  const ExperimentRun select = BuildExperimentRun(p, Phase::kSelect, 11, 0.0, config);
  const ExperimentRun val = BuildExperimentRun(p, Phase::kValidate, 11, 0.0, config);
  const ExperimentRun again = BuildExperimentRun(p, Phase::kTrain, 11, 0.0, config);
  const ExperimentRun select_again = BuildExperimentRun(p, Phase::kSelect, 11, 0.0, config);
  EXPECT_EQ(train.commands.size(), static_cast<std::size_t>(p.train_duration_s * 100 + 0.5));
  EXPECT_EQ(select.commands.size(), static_cast<std::size_t>(p.select_duration_s * 100 + 0.5));
  EXPECT_EQ(val.commands.size(), static_cast<std::size_t>(p.validate_duration_s * 100 + 0.5));

  // Same seed ⇒ bit-identical; the three phases differ pairwise.
  ASSERT_EQ(train.commands.size(), again.commands.size());
  for (std::size_t k = 0; k < train.commands.size(); ++k) {
    ASSERT_TRUE(train.commands[k] == again.commands[k]);
  }
  ASSERT_EQ(select.commands.size(), select_again.commands.size());
  for (std::size_t k = 0; k < select.commands.size(); ++k) {
    ASSERT_TRUE(select.commands[k] == select_again.commands[k]);
  }
  EXPECT_GT(MaxDifference(train, val), 1e-3);
  EXPECT_GT(MaxDifference(train, select), 1e-3);
  EXPECT_GT(MaxDifference(select, val), 1e-3);
  EXPECT_EQ(train.excitation_values, again.excitation_values);
  EXPECT_EQ(select.excitation_values, select_again.excitation_values);
  EXPECT_EQ(select.excitation_names, train.excitation_names);
  EXPECT_EQ(train.record_applied, p.attitude_hold);

  // Designed within the actuator limits (the builder's clamp never had to act), and excited
  // (not constant).
  for (const ExperimentRun* run : {&train, &select, &val}) {
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

  // Input columns exist: a command column, an excitation column of the run, (for a run that
  // records it) an applied-command column, or a beat-averaged state.
  for (const std::string& in : p.input_columns) {
    const bool is_command =
        in.rfind("w1_", 0) == 0 || (in.size() > 4 && in.substr(in.size() - 4) == "_avg");
    bool is_excitation = false;
    for (const std::string& name : train.excitation_names) is_excitation |= name == in;
    for (const std::string& name : vehicle::AppliedChannelNames())
      is_excitation |= train.record_applied && name == in;
    EXPECT_TRUE(is_command || is_excitation) << in;
  }
  // Without the hold, the applied channel of a designed command is the excitation itself.
  if (train.record_applied) {
    const std::string& u = train.excitation_names.at(0);
    const std::string applied = u.substr(0, u.size() - 4) + "_applied_rad";
    const auto& names = vehicle::AppliedChannelNames();
    const std::size_t channel =
        static_cast<std::size_t>(std::find(names.begin(), names.end(), applied) - names.begin());
    ASSERT_LT(channel, names.size()) << applied;
    for (std::size_t k = 0; k < train.commands.size(); ++k) {
      ASSERT_EQ(vehicle::AppliedChannelValues(train.commands[k], train.trim.amp_rad)[channel],
                train.excitation_values[0][k])
          << k;
    }
  }

  if (!p.clamped_body) {
    // Free flight starts at hover trim, in the air.
    EXPECT_NEAR(train.initial.state.position_m.z(), 50.0, 1e-12);
    EXPECT_TRUE(train.initial.prior_command == train.trim.command);
    // Attitude excitations are zero-mean.
    if (p.name != "vertical_velocity" && p.name != "vertical_wide" && p.name != "battery_sag") {
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
                                           "roll", "pitch", "yaw", "roll_held", "pitch_held"));
INSTANTIATE_TEST_SUITE_P(BeyondPaper, EveryPreset,
                         ::testing::Values("vertical_wide", "force_map_fz", "roll_coupled",
                                           "wing_damage", "battery_sag"));

// The experiments beyond the paper: nonlinear physics, identified at a decimated rate from
// signals the identifier can read live (an applied channel, an excitation column of the run, a
// command column on the test stand, or a beat average).
TEST(Presets, BeyondThePaperAreDecimatedAndReadLiveSignals) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  int count = 0;
  for (const ExperimentPreset& p : Presets()) {
    if (!p.beyond_paper) continue;
    SCOPED_TRACE(p.name);
    ++count;
    const bool damage = std::isfinite(p.validate_damage.at_s);
    if (!damage) {
      EXPECT_GT(p.decimate, 1);
    }
    EXPECT_FALSE(p.held_vehicle);
    EXPECT_EQ(p.paper_accuracy_text, "not in the paper");
    const ExperimentRun run = BuildExperimentRun(p, Phase::kTrain, 1, 0.0, config);
    for (const std::string& in : p.input_columns) {
      const auto& applied = vehicle::AppliedChannelNames();
      const bool ok =
          (p.attitude_hold && std::find(applied.begin(), applied.end(), in) != applied.end()) ||
          std::find(run.excitation_names.begin(), run.excitation_names.end(), in) !=
              run.excitation_names.end() ||
          (p.clamped_body && in.rfind("w1_", 0) == 0) ||
          (in.size() > 4 && in.substr(in.size() - 4) == "_avg");
      EXPECT_TRUE(ok) << in;
    }
  }
  EXPECT_EQ(count, 5);
}

// The damage presets damage the vehicle halfway through the validation run, and only there.
TEST(Presets, DamagePresetsChangeTheVehicleOnlyInValidation) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  for (const char* name : {"wing_damage", "battery_sag"}) {
    SCOPED_TRACE(name);
    const ExperimentPreset& p = *FindPreset(name);
    EXPECT_NE(p.description.find("DAMAGE"), std::string::npos);
    EXPECT_DOUBLE_EQ(p.validate_damage.at_s, 0.5 * p.validate_duration_s);
    EXPECT_EQ(p.validate_damage.Problems(), "");
    for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
      const ExperimentRun run = BuildExperimentRun(p, phase, 1, 2.0, config);
      EXPECT_EQ(std::isfinite(run.damage.at_s), phase == Phase::kValidate) << PhaseName(phase);
    }
  }
  EXPECT_DOUBLE_EQ(FindPreset("wing_damage")->validate_damage.amplitude_scale, 0.7);
  EXPECT_EQ(FindPreset("wing_damage")->validate_damage.wing, 1);
  EXPECT_DOUBLE_EQ(FindPreset("battery_sag")->validate_damage.frequency_scale, 0.9);
  EXPECT_EQ(FindPreset("battery_sag")->validate_damage.wing, 0);
  // Every other preset flies an intact vehicle in every phase.
  for (const ExperimentPreset& p : Presets()) {
    if (p.name == "wing_damage" || p.name == "battery_sag") continue;
    EXPECT_FALSE(std::isfinite(BuildExperimentRun(p, Phase::kValidate, 1, 1.0, config).damage.at_s))
        << p.name;
  }
}

// The force map changes its levels only at decimation-block boundaries, so each decimated row's
// input is one level; every block differs from the one before in all three inputs.
TEST(Presets, ForceMapLevelsAreAlignedToTheDecimationBlocks) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  const ExperimentPreset& p = *FindPreset("force_map_fz");
  for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
    const ExperimentRun run = BuildExperimentRun(p, phase, 2, 0.0, config);
    const auto block = static_cast<std::size_t>(p.decimate);
    for (std::size_t k = 0; k < run.commands.size(); ++k) {
      ASSERT_TRUE(run.commands[k] == run.commands[k - k % block]) << PhaseName(phase) << " " << k;
      // All four wings fly the same command.
      for (int w = 1; w < plant::kWingCount; ++w) {
        ASSERT_TRUE(run.commands[k].row(w) == run.commands[k].row(0));
      }
    }
    for (std::size_t k = block; k < run.commands.size(); k += block) {
      for (const int input :
           {plant::kFlapFrequency, plant::kStrokeAmplitude, plant::kStrokePlaneAngle}) {
        EXPECT_NE(run.commands[k](0, input), run.commands[k - block](0, input)) << k;
      }
    }
  }
}

// A held variant flies exactly the runs of its preset.
TEST(Presets, HeldVariantsFlyTheSameRuns) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  for (const char* base : {"roll", "pitch"}) {
    for (const Phase phase : {Phase::kTrain, Phase::kSelect, Phase::kValidate}) {
      const ExperimentRun a = BuildExperimentRun(*FindPreset(base), phase, 3, 2.0, config);
      const ExperimentRun b =
          BuildExperimentRun(*FindPreset(std::string(base) + "_held"), phase, 3, 2.0, config);
      ASSERT_EQ(a.commands.size(), b.commands.size());
      for (std::size_t k = 0; k < a.commands.size(); ++k)
        ASSERT_TRUE(a.commands[k] == b.commands[k]);
      EXPECT_EQ(a.excitation_values, b.excitation_values);
    }
  }
}

}  // namespace
}  // namespace odonata::experiments

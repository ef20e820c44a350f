// CommandSchedule: a preset gives odonata-sim's commands; a command file is read as odonata-sim
// reads it, with u_* columns as excitations and out-of-limit rows refused up front.
#include "pipeline/command_schedule.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

namespace odonata::pipeline {
namespace {

class CommandScheduleTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char tmpl[] = "/tmp/odonata_schedule_test_XXXXXX";
    ASSERT_NE(mkdtemp(tmpl), nullptr);
    dir_ = tmpl;
    config_ = plant::DefaultPlantConfig();
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }

  // A command file of `rows` samples at the nominal command; `amp_last` sets w3_amp_rad of the
  // last row.
  std::string WriteFile(int rows, double amp_last, double dt_s = 0.01) {
    std::string header = "t_s";
    for (int w = 0; w < plant::kWingCount; ++w)
      for (int i = 0; i < plant::kCommandsPerWing; ++i)
        header += "," + plant::CommandColumnName(w, i);
    header += ",u_test_rad,vx_mps";
    const std::string path = dir_ + "/commands.csv";
    std::ofstream out(path);
    out.precision(17);  // lossless, as odonata-sim writes
    out << header << "\n";
    for (int k = 0; k < rows; ++k) {
      out << k * dt_s;
      for (int w = 0; w < plant::kWingCount; ++w) {
        for (int i = 0; i < plant::kCommandsPerWing; ++i) {
          const double v = (k == rows - 1 && w == 2 && i == plant::kStrokeAmplitude)
                               ? amp_last
                               : config_.nominal_command(i);
          out << "," << v;
        }
      }
      out << "," << 0.5 * k << ",0\n";
    }
    return path;
  }

  std::string dir_;
  plant::PlantConfig config_;
};

TEST_F(CommandScheduleTest, PresetMatchesBuildExperimentRun) {
  const auto& preset = *experiments::FindPreset("pitch");
  const CommandSchedule s = PresetSchedule(preset, experiments::Phase::kValidate, 4, 0.5, config_);
  const auto run =
      experiments::BuildExperimentRun(preset, experiments::Phase::kValidate, 4, 0.5, config_);
  ASSERT_EQ(s.size(), 50u);
  for (std::size_t k = 0; k < s.size(); ++k) EXPECT_EQ(s.commands[k], run.commands[k]);
  EXPECT_EQ(s.excitation_names, std::vector<std::string>{"u_pitch_rad"});
  EXPECT_EQ(s.excitation_values, run.excitation_values);
  EXPECT_EQ(s.source, "preset:pitch/validate");
  EXPECT_EQ(s.setup_name, "pitch");
  EXPECT_EQ(s.TimeOf(7), 7 * 0.01);
}

TEST_F(CommandScheduleTest, FileWithExcitationColumnsAndDuration) {
  const std::string path = WriteFile(20, 1.0);
  const CommandSchedule s = FileSchedule(path, config_, 0.1);
  ASSERT_EQ(s.size(), 10u);
  EXPECT_EQ(s.source, path);
  EXPECT_EQ(s.setup_name, "");
  EXPECT_EQ(s.commands[3], plant::UniformCommand(config_.nominal_command));
  ASSERT_EQ(s.excitation_names, std::vector<std::string>{"u_test_rad"});  // vx_mps is not one
  ASSERT_EQ(s.excitation_values[0].size(), 10u);
  EXPECT_EQ(s.excitation_values[0][4], 2.0);
}

TEST_F(CommandScheduleTest, FileOutsideLimitsOrBadSpacingIsRefused) {
  try {
    FileSchedule(WriteFile(5, 2.0), config_, 0.0);
    FAIL() << "accepted a command outside the limits";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("sample 4: w3_amp_rad = 2"), std::string::npos)
        << e.what();
  }
  EXPECT_NO_THROW(FileSchedule(WriteFile(5, 2.0), config_, 0.04));  // the bad row is cut off
  EXPECT_THROW(FileSchedule(WriteFile(5, 1.0, 0.02), config_, 0.0), std::runtime_error);
}

}  // namespace
}  // namespace odonata::pipeline

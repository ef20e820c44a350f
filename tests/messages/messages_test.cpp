// The vehicle's messages ⇄ the plant's types: every named signal reads back the value the plant
// produced, under the name odonata-sim gives its column.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "experiments/experiment_preset.hpp"
#include "experiments/sample_columns.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/paired_sample.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"
#include "pipeline/vehicle_setup.hpp"
#include "plant/output_signals.hpp"

namespace odonata::messages {
namespace {

// A sample whose every field differs, so a swapped field cannot go unseen.
pipeline::PlantSample DistinctSample() {
  pipeline::PlantSample s;
  s.seq = 7;
  s.command_seq = 6;
  double v = 1.0;
  auto next = [&v] { return v += 0.25; };
  plant::PlantOutput& o = s.output;
  o.time_s = 0.07;
  for (int i = 0; i < 3; ++i) {
    o.velocity_body_mps(i) = next();
    o.rate_body_radps(i) = next();
    o.position_m(i) = next();
  }
  o.roll_rad = next();
  o.pitch_rad = next();
  o.yaw_rad = next();
  for (int w = 0; w < plant::kWingCount; ++w) {
    o.force_x_n(w) = next();
    o.force_z_n(w) = next();
  }
  o.beat.window_s = next();
  for (int i = 0; i < 3; ++i) {
    o.beat.velocity_body_mps(i) = next();
    o.beat.rate_body_radps(i) = next();
  }
  o.beat.roll_rad = next();
  o.beat.pitch_rad = next();
  o.beat.yaw_rad = next();
  o.beat.force_x_n = next();
  o.beat.force_z_n = next();
  for (int w = 0; w < plant::kWingCount; ++w)
    for (int i = 0; i < plant::kCommandsPerWing; ++i) s.applied_command(w, i) = next();
  return s;
}

TEST(Messages, EveryOutputNameReadsThePlantsValueFromTheStateMessage) {
  const pipeline::PlantSample s = DistinctSample();
  const odonata::plant_state_t m = ToStateMessage(s, 123);
  EXPECT_EQ(m.utime, 123);
  EXPECT_EQ(m.seq, 7);
  EXPECT_EQ(m.command_seq, 6);
  const auto values = plant::StateSignalValues(s.output);
  ASSERT_EQ(plant::StateSignalNames().size(), values.size());
  for (std::size_t i = 0; i < values.size(); ++i)
    EXPECT_EQ(*StateField(m, plant::StateSignalNames()[i]), values[i])
        << plant::StateSignalNames()[i];
  EXPECT_EQ(*StateField(m, "z_m"), s.output.position_m(2));
  EXPECT_EQ(*StateField(m, "fz3_n"), s.output.force_z_n(2));
  EXPECT_FALSE(StateField(m, "no_such_signal"));
  EXPECT_TRUE(AllFinite(m));
  odonata::plant_state_t bad = m;
  bad.fz_n[3] = std::nan("");
  EXPECT_FALSE(AllFinite(bad));
}

TEST(Messages, BeatAveragesAndAppliedChannelsReadBackFromTheBeatState) {
  const pipeline::PlantSample s = DistinctSample();
  pipeline::VehicleSetup setup;
  setup.trim_command.setConstant(0.5);
  const odonata::beat_state_t m = ToBeatStateMessage(s, setup, 5);
  const auto values = plant::BeatSignalValues(s.output.beat);
  for (std::size_t i = 0; i < values.size(); ++i) {
    const std::string& name = plant::BeatSignalNames()[i];
    EXPECT_EQ(*BeatStateField(m, name), values[i]) << name;
    EXPECT_EQ(BeatStateOffset(name), 0) << name;
  }
  const auto applied = vehicle::AppliedChannelValues(s.applied_command, 0.5);
  for (std::size_t i = 0; i < applied.size(); ++i) {
    const std::string& name = vehicle::AppliedChannelNames()[i];
    EXPECT_EQ(*BeatStateField(m, name), applied[i]) << name;
    EXPECT_EQ(BeatStateOffset(name), 1) << name;
  }
  EXPECT_EQ(*BeatStateField(m, "window_s"), s.output.beat.window_s);
  EXPECT_FALSE(BeatStateOffset("vz_mps"));
  EXPECT_TRUE(AllFinite(m));
}

TEST(Messages, CommandMatrixRoundTripsThroughTheMessageUnderOdonataSimsColumnNames) {
  pipeline::CommandSchedule schedule;
  schedule.sample_period_s = 0.01;
  schedule.commands.resize(3);
  for (std::size_t k = 0; k < 3; ++k)
    for (int w = 0; w < plant::kWingCount; ++w)
      for (int i = 0; i < plant::kCommandsPerWing; ++i)
        schedule.commands[k](w, i) = 100.0 * k + 10.0 * w + i;
  schedule.excitation_names = {"u_roll_rad"};
  schedule.excitation_values = {{0.1, 0.2, 0.3}};
  const odonata::wing_command_t m = ToCommandMessage(schedule, 2, 9);
  EXPECT_EQ(m.seq, 2);
  EXPECT_DOUBLE_EQ(m.t_s, 0.02);
  EXPECT_EQ(ToCommandMatrix(m), schedule.commands[2]);
  const auto& names = experiments::CommandSignalNames();
  ASSERT_EQ(names.size(), 24u);
  for (int w = 0; w < plant::kWingCount; ++w)
    for (int i = 0; i < plant::kCommandsPerWing; ++i)
      EXPECT_EQ(*CommandField(m, names[static_cast<std::size_t>(w * plant::kCommandsPerWing + i)]),
                schedule.commands[2](w, i));
  EXPECT_EQ(*CommandField(m, "u_roll_rad"), 0.3);
  EXPECT_EQ(CountProblems(m), "");
  odonata::wing_command_t bad = m;
  bad.num_excitations = 2;
  EXPECT_NE(CountProblems(bad), "");
}

TEST(Messages, APairedSampleReadsEachSignalFromTheMessageThatCarriesIt) {
  const pipeline::PlantSample s = DistinctSample();
  PairedMessages e;
  e.state = ToStateMessage(s, 0);
  pipeline::CommandSchedule schedule;
  schedule.sample_period_s = 0.01;
  schedule.commands.assign(8, plant::CommandMatrix::Constant(0.75));
  e.command = ToCommandMessage(schedule, 7, 0);
  pipeline::VehicleSetup setup;
  e.beat = ToBeatStateMessage(s, setup, 0);
  EXPECT_EQ(*PairedSignal(e, "roll_rad"), s.output.roll_rad);
  EXPECT_EQ(*PairedSignal(e, "w2_amp_rad"), 0.75);
  EXPECT_EQ(*PairedSignal(e, "roll_rad_avg"), s.output.beat.roll_rad);
  EXPECT_EQ(*PairedSignal(e, "t_s"), s.output.time_s);
  // The applied channels come from beat state k + 1, which this sample was paired without.
  EXPECT_THROW(PairedSignal(e, "u_roll_applied_rad"), std::invalid_argument);
  const pipeline::PairingNeeds needs = PairingNeedsOf({"roll_rad", "u_roll_applied_rad"});
  EXPECT_FALSE(needs.beat);
  EXPECT_TRUE(needs.next_beat);
}

TEST(SampleColumns, DecimationAveragesWhatHoldsOverASampleAndSamplesTheRest) {
  for (const auto& n : plant::StateSignalNames()) EXPECT_FALSE(experiments::IsAveragedSignal(n));
  for (const auto& n : plant::BeatSignalNames()) EXPECT_FALSE(experiments::IsAveragedSignal(n));
  for (const auto& n : experiments::CommandSignalNames())
    EXPECT_TRUE(experiments::IsAveragedSignal(n));
  for (const auto& n : vehicle::AppliedChannelNames())
    EXPECT_TRUE(experiments::IsAveragedSignal(n));
  EXPECT_TRUE(experiments::IsAveragedSignal("u_roll_rad"));  // an excitation
  EXPECT_FALSE(experiments::IsAveragedSignal("t_s"));
  const auto h = experiments::SampleColumnNames({"u_x"}, true, false);
  EXPECT_EQ(h.size(), 1 + 24 + 20 + 1 + 11u);
  EXPECT_EQ(h.front(), "t_s");
  EXPECT_EQ(h[1 + 24 + 20], "u_x");
}

}  // namespace
}  // namespace odonata::messages

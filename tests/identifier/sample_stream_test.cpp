// SampleStream: the identifier's samples from the vehicle's messages, without a bus.
#include "sample_stream.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace odonata::identifier {
namespace {

odonata::plant_state_t State(int64_t k) {
  odonata::plant_state_t s{};
  s.seq = k;
  s.command_seq = k - 1;
  s.t_s = 0.01 * static_cast<double>(k);
  s.attitude_rad[0] = 0.1 * static_cast<double>(k);  // roll_rad
  return s;
}

odonata::wing_command_t Command(int64_t k) {
  odonata::wing_command_t c{};
  c.seq = k;
  c.source = "gen";
  c.num_excitations = 1;
  c.excitation_names = {"u_roll_rad"};
  c.excitations = {static_cast<double>(k)};
  return c;
}

sysid::RegressorSpec Spec() {
  sysid::RegressorSpec spec;
  spec.outputs = {"roll_rad"};
  spec.inputs = {"u_roll_rad"};
  return spec;
}

std::vector<sysid::Sample> Samples(const std::vector<SampleStream::Event>& events) {
  std::vector<sysid::Sample> out;
  for (const auto& e : events)
    if (e.kind == SampleStream::Event::Kind::kSample) out.push_back(e.sample);
  return out;
}

TEST(SampleStream, SampleKJoinsStateKWithTheCommandStateKPlusOneAnswers) {
  SampleStream stream(Spec(), 1);
  stream.Start();
  EXPECT_FALSE(stream.needs_beat_states());
  std::vector<sysid::Sample> got;
  for (int64_t k = 0; k < 4; ++k) {
    for (auto& s : Samples(stream.OnState(State(k)))) got.push_back(s);
    for (auto& s : Samples(stream.OnCommand(Command(k)))) got.push_back(s);
  }
  ASSERT_EQ(got.size(), 3u);
  for (std::size_t k = 0; k < got.size(); ++k) {
    EXPECT_EQ(got[k].index, static_cast<int64_t>(k));
    EXPECT_DOUBLE_EQ(got[k].outputs(0), 0.1 * static_cast<double>(k));
    EXPECT_DOUBLE_EQ(got[k].inputs(0), static_cast<double>(k));
  }
}

TEST(SampleStream, DecimationAveragesTheInputAndSamplesTheOutputPerBlock) {
  SampleStream stream(Spec(), 2);
  stream.Start();
  std::vector<sysid::Sample> got;
  for (int64_t k = 0; k < 6; ++k) {
    for (auto& s : Samples(stream.OnState(State(k)))) got.push_back(s);
    for (auto& s : Samples(stream.OnCommand(Command(k)))) got.push_back(s);
  }
  ASSERT_EQ(got.size(), 2u);  // blocks {0, 1} and {2, 3}; {4, 5} waits for state 6
  EXPECT_EQ(got[1].index, 1);
  EXPECT_DOUBLE_EQ(got[1].outputs(0), 0.2);  // roll at the block's first sample
  EXPECT_DOUBLE_EQ(got[1].inputs(0), 2.5);   // the mean of commands 2 and 3
}

TEST(SampleStream, BeforeStartMessagesArePairedButMakeNoSample) {
  SampleStream stream(Spec(), 1);
  for (int64_t k = 0; k < 3; ++k) {
    EXPECT_TRUE(Samples(stream.OnState(State(k))).empty());
    EXPECT_TRUE(Samples(stream.OnCommand(Command(k))).empty());
  }
  EXPECT_EQ(stream.newest_held_state(), 2);
  stream.Start();
  EXPECT_EQ(Samples(stream.OnState(State(3))).size(), 1u);
}

TEST(SampleStream, BadMessagesAreRejectedAndARestartIsReported) {
  SampleStream stream(Spec(), 1);
  stream.Start();
  odonata::plant_state_t nan = State(0);
  nan.velocity_mps[1] = std::nan("");
  EXPECT_THROW(stream.OnState(nan), std::invalid_argument);
  odonata::wing_command_t ragged = Command(0);
  ragged.num_excitations = 3;
  EXPECT_THROW(stream.OnCommand(ragged), std::invalid_argument);
  for (int64_t k = 0; k < 3; ++k) {
    stream.OnState(State(k));
    stream.OnCommand(Command(k));
  }
  // A fresh state 0 is a restart once the plant confirms it with its state 1.
  EXPECT_TRUE(stream.OnState(State(0)).empty());
  stream.OnCommand(Command(0));
  const auto events = stream.OnState(State(1));
  ASSERT_FALSE(events.empty());
  EXPECT_EQ(events.front().kind, SampleStream::Event::Kind::kRestart);
}

}  // namespace
}  // namespace odonata::identifier

namespace odonata::identifier {
namespace {

odonata::signals_t Signals(int64_t k, double y, double u) {
  odonata::signals_t m{};
  m.seq = k;
  m.source = "my-drone";
  m.num_signals = 3;
  m.names = {"battery_v", "u_roll_rad", "roll_rad"};  // any order, extra signals ignored
  m.values = {NAN, u, y};
  return m;
}

// Any vehicle's signals_t: sample k straight from message k, by name, whatever else it carries.
TEST(SampleStreamSignals, SampleKIsMessageKByNameAndGapsRestartsAndLeapsAreSeen) {
  SampleStream stream(Spec(), 1);
  EXPECT_TRUE(Samples(stream.OnSignals(Signals(0, 0.5, 1.0))).empty());  // not started yet
  stream.Start();
  auto got = Samples(stream.OnSignals(Signals(1, 0.25, -1.0)));
  ASSERT_EQ(got.size(), 1u);
  EXPECT_EQ(got[0].index, 1);
  EXPECT_EQ(got[0].outputs(0), 0.25);
  EXPECT_EQ(got[0].inputs(0), -1.0);
  // Duplicates and stale samples are refused; a lost sample is a gap.
  EXPECT_THROW(stream.OnSignals(Signals(1, 0, 0)), std::invalid_argument);
  auto events = stream.OnSignals(Signals(4, 0.1, 0.2));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, SampleStream::Event::Kind::kGap);
  EXPECT_EQ(events[0].lost, 2);
  EXPECT_EQ(events[1].sample.index, 4);
  // A far leap is held until the next seq confirms it, so one forged packet cannot stall a run.
  EXPECT_THROW(stream.OnSignals(Signals(900000, 0, 0)), std::invalid_argument);
  EXPECT_EQ(Samples(stream.OnSignals(Signals(5, 0.3, 0.4))).size(), 1u);
  // seq 0 again: the vehicle restarted.
  events = stream.OnSignals(Signals(0, 0.7, 0.8));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, SampleStream::Event::Kind::kRestart);
  EXPECT_EQ(events[1].sample.index, 0);
}

TEST(SampleStreamSignals, ARestartWhoseSeqZeroWasLostIsConfirmedByTheNextSeq) {
  SampleStream stream(Spec(), 1);
  stream.Start();
  for (int64_t k = 0; k <= 500; ++k) stream.OnSignals(Signals(k, 0.1, 0.2));
  // One stray old packet is dropped and restarts nothing ...
  EXPECT_THROW(stream.OnSignals(Signals(3, 0.1, 0.2)), std::invalid_argument);
  EXPECT_EQ(Samples(stream.OnSignals(Signals(501, 0.1, 0.2))).size(), 1u);
  EXPECT_THROW(stream.OnSignals(Signals(4, 0.1, 0.2)), std::invalid_argument);  // not after 3
  EXPECT_EQ(Samples(stream.OnSignals(Signals(502, 0.1, 0.2))).size(), 1u);
  // ... but seq 1 then seq 2 of a restarted vehicle (its seq 0 lost) is a restart at seq 2.
  EXPECT_THROW(stream.OnSignals(Signals(1, 0.1, 0.2)), std::invalid_argument);
  const auto events = stream.OnSignals(Signals(2, 0.1, 0.2));
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, SampleStream::Event::Kind::kRestart);
  EXPECT_EQ(events[1].sample.index, 2);
  EXPECT_EQ(Samples(stream.OnSignals(Signals(3, 0.1, 0.2))).size(), 1u);
}

TEST(SampleStreamSignals, AMissingOrNonFiniteModelSignalOrBadCountsAreRefused) {
  SampleStream stream(Spec(), 1);
  stream.Start();
  auto m = Signals(0, NAN, 1.0);
  EXPECT_THROW(stream.OnSignals(m), std::invalid_argument);  // roll_rad is NaN
  m = Signals(1, 0.1, 1.0);
  m.names[2] = "pitch_rad";  // no roll_rad at all
  EXPECT_THROW(stream.OnSignals(m), std::invalid_argument);
  m = Signals(2, 0.1, 1.0);
  m.num_signals = 5;
  EXPECT_THROW(stream.OnSignals(m), std::invalid_argument);
  m = Signals(3, 0.1, 1.0);
  m.names[0] = "roll_rad";  // twice
  EXPECT_THROW(stream.OnSignals(m), std::invalid_argument);
  EXPECT_EQ(Samples(stream.OnSignals(Signals(4, 0.1, 1.0))).size(), 1u);
}

TEST(SampleStreamSignals, DecimatesLikeTheCommandAndStatePath) {
  SampleStream stream(Spec(), 2);
  stream.Start();
  std::vector<sysid::Sample> got;
  for (int64_t k = 0; k < 6; ++k) {
    const auto s = Samples(stream.OnSignals(Signals(k, static_cast<double>(k), 2.0 * k)));
    got.insert(got.end(), s.begin(), s.end());
  }
  ASSERT_EQ(got.size(), 3u);
  EXPECT_EQ(got[1].index, 1);  // block 1: samples 2 and 3
}

}  // namespace
}  // namespace odonata::identifier

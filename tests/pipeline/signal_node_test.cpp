// SignalNode over memq://: with the real PlantNode on the same bus (a complete lockstep run in one
// process), with a fake plant that loses a message, and with no plant at all.
#include "signal_node.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <map>
#include <set>

#include "experiments/experiment_preset.hpp"
#include "experiments/sample_columns.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"
#include "odonata/heartbeat_t.hpp"
#include "pipeline/plant_session.hpp"
#include "plant/output_signals.hpp"
#include "plant_node.hpp"
#include "support/memq_bus.hpp"

namespace odonata::signal_service {
namespace {

// One bus for both nodes, named as the plant, so control messages reach the plant.
bus::BusOptions MemqOptions() { return testing::MemqOptions("odonata-plant"); }

pipeline::CommandSchedule Roll(double duration_s) {
  return pipeline::PresetSchedule(*experiments::FindPreset("roll"), experiments::Phase::kTrain, 1,
                                  duration_s, plant::DefaultPlantConfig());
}

// Runs the bus until the signal node stops it; a fence stops a hung run with code 99.
int RunFenced(bus::BusNode& bus, int seconds = 10) {
  bus.After(std::chrono::seconds(seconds), [&bus] { bus.Stop(99); });
  return bus.Run();
}

TEST(SignalNode, CommandMessageCarriesCommandsExcitationAndSource) {
  const pipeline::CommandSchedule s = Roll(0.1);
  const odonata::wing_command_t m = messages::ToCommandMessage(s, 4, 0);
  EXPECT_EQ(m.seq, 4);
  EXPECT_EQ(m.t_s, s.TimeOf(4));
  EXPECT_EQ(m.source, "preset:roll/train");
  ASSERT_EQ(m.num_excitations, 1);
  ASSERT_EQ(m.excitations.size(), 1u);
  EXPECT_EQ(m.excitation_names[0], "u_roll_rad");
  EXPECT_EQ(m.excitations[0], s.excitation_values[0][4]);
  EXPECT_EQ(*messages::CommandField(m, "w3_amp_rad"), s.commands[4](2, plant::kStrokeAmplitude));
  EXPECT_EQ(*messages::CommandField(m, "w1_freq_hz"), s.commands[4](0, plant::kFlapFrequency));
  EXPECT_EQ(messages::CountProblems(m), "");
}

TEST(SignalNode, LockstepRunWithThePlantNodeMatchesTheOfflineSession) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  bus::BusNode bus(MemqOptions());
  std::map<int64_t, odonata::plant_state_t> states;
  bus.Subscribe<odonata::plant_state_t>(bus.channels().state,
                                        [&](const auto& m) { states[m.seq] = m; });
  // The plant starts on the test stand; the generator's RESET must switch it to free flight.
  plant_service::PlantNode plant(bus, config, pipeline::PlantSession::Mode::kLockstep,
                                 "actuator_fz");
  const pipeline::CommandSchedule schedule = Roll(0.3);
  SignalOptions options;
  options.timeout_ms = 500;
  SignalNode signal(bus, schedule, options);
  ASSERT_EQ(RunFenced(bus), 0);
  EXPECT_EQ(signal.commands_sent(), 30);
  EXPECT_EQ(signal.sequencer().total_resends(), 0);

  pipeline::PlantSession reference(config, pipeline::PlantSession::Mode::kLockstep,
                                   pipeline::VehicleSetupByName("roll", config));
  ASSERT_EQ(states.size(), 31u);
  for (int64_t k = 0; k <= 30; ++k) {
    if (k > 0) reference.Submit(k - 1, schedule.commands[static_cast<std::size_t>(k - 1)]);
    const odonata::plant_state_t expected = messages::ToStateMessage(reference.last(), 0);
    const odonata::plant_state_t& got = states.at(k);
    EXPECT_EQ(got.command_seq, k - 1);
    for (const std::string& name : plant::StateSignalNames()) {
      const double a = *messages::StateField(got, name), b = *messages::StateField(expected, name);
      ASSERT_EQ(std::memcmp(&a, &b, sizeof a), 0) << name << " at sample " << k;
    }
  }
}

// A fake plant's answer to command `seq`: state seq + 1.
void AnswerCommand(bus::BusNode& bus, int64_t seq) {
  odonata::plant_state_t s{};
  s.seq = seq + 1;
  s.command_seq = seq;
  bus.Publish(bus.channels().state, s);
}

// A fake plant's reset: a fresh state 0.
void AnswerResetWithStateZero(bus::BusNode& bus) {
  bus.Subscribe<odonata::control_t>(bus.channels().control, [&bus](const auto& c) {
    if (c.command != odonata::control_t::RESET) return;
    odonata::plant_state_t s{};
    s.command_seq = -1;
    bus.Publish(bus.channels().state, s);
  });
}

TEST(SignalNode, ResendsACommandWhoseAnswerWasLost) {
  bus::BusNode bus(MemqOptions());
  std::map<int64_t, int> received;  // command seq → times seen
  // A fake plant that answers every command but the first copy of command 3.
  bus.Subscribe<odonata::wing_command_t>(bus.channels().command, [&](const auto& m) {
    if (++received[m.seq] == 1 && m.seq == 3) return;
    AnswerCommand(bus, m.seq);
  });
  AnswerResetWithStateZero(bus);
  SignalOptions options;
  options.timeout_ms = 20;
  options.window = 1;
  SignalNode signal(bus, Roll(0.1), options);
  ASSERT_EQ(RunFenced(bus), 0);
  EXPECT_EQ(received.size(), 10u);
  EXPECT_EQ(received[3], 2);
  EXPECT_EQ(received[4], 1);
  EXPECT_EQ(signal.sequencer().total_resends(), 1);
}

// A window of 4: the plant applies in seq order, so losing command 3 holds 4 … 6 back until the
// timeout resends the window from 3 on; the plant answers the applied ones again.
TEST(SignalNode, AWindowResendsEverythingInFlightFromTheOldestUnconfirmedCommand) {
  bus::BusNode bus(MemqOptions());
  std::map<int64_t, int> received;  // command seq → times seen
  int64_t next = 0;                 // the in-order plant's next command
  std::set<int64_t> held;
  const auto answer = [&bus](int64_t seq) { AnswerCommand(bus, seq); };
  bus.Subscribe<odonata::wing_command_t>(bus.channels().command, [&](const auto& m) {
    if (++received[m.seq] == 1 && m.seq == 3) return;  // lost on the way
    if (m.seq < next) return answer(m.seq);            // applied before: answered again
    held.insert(m.seq);
    while (held.count(next) > 0) {
      held.erase(next);
      answer(next++);
    }
  });
  AnswerResetWithStateZero(bus);
  SignalOptions options;
  options.timeout_ms = 20;
  options.window = 4;
  SignalNode signal(bus, Roll(0.1), options);
  ASSERT_EQ(RunFenced(bus), 0);
  EXPECT_EQ(next, 10);
  EXPECT_EQ(received[2], 1);
  for (int64_t k = 3; k <= 6; ++k) EXPECT_EQ(received[k], 2) << k;
  EXPECT_EQ(received[7], 1);
  EXPECT_EQ(signal.sequencer().total_resends(), 1);
  EXPECT_EQ(signal.commands_sent(), 14);
}

TEST(SignalNode, MissingPlantFailsAfterTheResends) {
  bus::BusNode bus(MemqOptions());
  int resets = 0;
  bus.Subscribe<odonata::control_t>(bus.channels().control, [&](const auto& c) {
    if (c.command == odonata::control_t::RESET && c.path == "roll" && c.target == "odonata-plant")
      ++resets;
  });
  SignalOptions options;
  options.timeout_ms = 10;
  options.max_resends = 3;
  SignalNode signal(bus, Roll(0.1), options);
  const auto start = std::chrono::steady_clock::now();
  EXPECT_EQ(RunFenced(bus), kExitNoPlant);
  EXPECT_LT(std::chrono::steady_clock::now() - start, std::chrono::seconds(2));
  EXPECT_EQ(resets, 4);  // the first RESET and three resends
  EXPECT_EQ(signal.commands_sent(), 0);
  EXPECT_NE(bus.stats().last_error.find("odonata-plant"), std::string::npos)
      << bus.stats().last_error;
}

TEST(SignalNode, RealtimeSendsOnTheClockWithoutAPlant) {
  bus::BusNode bus(MemqOptions());
  std::vector<int64_t> seqs;
  bus.Subscribe<odonata::wing_command_t>(bus.channels().command,
                                         [&](const auto& m) { seqs.push_back(m.seq); });
  SignalOptions options;
  options.lockstep = false;
  options.reset_plant = false;
  options.rate_hz = 200;
  const auto start = std::chrono::steady_clock::now();
  SignalNode signal(bus, Roll(0.2), options);  // 20 commands at 200 Hz ≈ 95 ms
  EXPECT_EQ(RunFenced(bus), 0);
  const double elapsed_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_GT(elapsed_s, 0.09);  // paced by the clock (an upper bound would time the machine)
  // The last command goes out just before Stop(); memq queues it undelivered, so ≥ 19 arrive.
  ASSERT_GE(seqs.size(), 19u);
  for (std::size_t i = 0; i < seqs.size(); ++i) EXPECT_EQ(seqs[i], static_cast<int64_t>(i));
}

// SIGTERM before the last command: the run is shorter than asked for, and the exit code says so
// (issue 24 point 8: it was 0, so a script took 2000 of 10000 commands for a whole run).
TEST(SignalNode, ASignalBeforeTheLastCommandIsNotASuccess) {
  bus::BusNode bus(MemqOptions());
  SignalOptions options;
  options.lockstep = false;
  options.reset_plant = false;
  options.rate_hz = 100;
  SignalNode signal(bus, Roll(10.0), options);  // 1000 commands: 10 s
  bus.After(std::chrono::milliseconds(100), [] { ::raise(SIGTERM); });
  EXPECT_EQ(RunFenced(bus), kExitInterrupted);
  EXPECT_TRUE(bus.stopped_by_signal());
  EXPECT_GT(signal.commands_sent(), 0);
  EXPECT_LT(signal.commands_sent(), 1000);
}

// A real-time plant answering each command with its next state, numbered from 0; from command
// `restart_at` on (if ≥ 0) it numbers them from 0 again, as a plant killed and started anew does,
// and before command `forge_at` (if ≥ 0) one lone state 0 arrives, as a stale or forged packet.
int RealtimeRunWithPlant(int64_t restart_at, int64_t forge_at, int64_t* commands_sent) {
  bus::BusNode bus(MemqOptions());
  int64_t next_state = 0;
  bus.Subscribe<odonata::wing_command_t>(bus.channels().command, [&](const auto& m) {
    if (m.seq == restart_at) next_state = 0;
    if (m.seq == forge_at) {
      odonata::plant_state_t lone{};
      lone.command_seq = -1;
      bus.Publish(bus.channels().state, lone);
    }
    odonata::plant_state_t s{};
    s.seq = next_state++;
    s.command_seq = m.seq;
    bus.Publish(bus.channels().state, s);
  });
  SignalOptions options;
  options.lockstep = false;
  options.reset_plant = false;
  options.rate_hz = 200;
  SignalNode signal(bus, Roll(0.4), options);  // 40 commands
  const int code = RunFenced(bus);
  *commands_sent = signal.commands_sent();
  return code;
}

// Issue 24 point 7: in real time a plant killed and restarted split the run unnoticed (exit 0).
TEST(SignalNode, RealtimeFlagsAPlantThatRestartedMidRun) {
  int64_t sent = 0;
  EXPECT_EQ(RealtimeRunWithPlant(20, -1, &sent), kExitPlantRestarted);
  EXPECT_EQ(sent, 40);  // the run goes on to its end: only its exit code tells
  EXPECT_EQ(RealtimeRunWithPlant(-1, -1, &sent), 0);
  // One state 0 alone is no restart: a stale or forged packet must not fail a whole run.
  EXPECT_EQ(RealtimeRunWithPlant(-1, 20, &sent), 0);
}

// A consumer that only ever says it is refitting (a forged heartbeat on a keyless bus, or a
// stuck identifier) holds a lockstep run for --refit-wait, then the run fails naming it. The
// default is under a minute without a key, where anyone can claim to be refitting, and 10 min
// with one.
TEST(SignalNode, AConsumerForeverRefittingFailsTheRunAfterTheRefitWait) {
  {
    bus::BusNode keyless(MemqOptions());
    SignalOptions options;
    const SignalNode signal(keyless, Roll(0.1), options);
    EXPECT_EQ(signal.sequencer().max_busy_timeouts() * options.timeout_ms,
              kKeylessRefitWaitS * 1000);
    EXPECT_LT(kKeylessRefitWaitS, 60);
  }
  {
    char path[] = "/tmp/odonata-signal-key-XXXXXX";
    const int fd = mkstemp(path);
    ASSERT_GE(fd, 0);
    const std::string hex(64, 'a');
    ASSERT_EQ(write(fd, hex.data(), hex.size()), 64);
    close(fd);
    bus::BusOptions o = MemqOptions();
    o.key_path = path;
    bus::BusNode signed_bus(o);
    SignalOptions options;
    const SignalNode signal(signed_bus, Roll(0.1), options);
    EXPECT_EQ(signal.sequencer().max_busy_timeouts() * options.timeout_ms,
              kSignedRefitWaitS * 1000);
    std::remove(path);
  }

  bus::BusNode bus(MemqOptions());
  bus.Subscribe<odonata::wing_command_t>(bus.channels().command,
                                         [&](const auto& m) { AnswerCommand(bus, m.seq); });
  AnswerResetWithStateZero(bus);
  bus.Every(std::chrono::milliseconds(5), [&] {
    odonata::heartbeat_t h{};
    h.utime = bus::NowUtime();
    h.service = "odonata-identifier";
    h.instance = "ghost";
    h.state = "refitting";
    bus.Publish(bus.channels().heartbeat, h);
  });
  SignalOptions options;
  options.timeout_ms = 10;
  options.max_resends = 2;
  options.refit_wait_s = 0.3;
  options.discover_s = 0.05;  // hears the ghost and waits for it
  SignalNode signal(bus, Roll(0.1), options);
  EXPECT_EQ(RunFenced(bus), kExitConsumerLost);
  EXPECT_EQ(signal.sequencer().busy_timeouts(), 30);
  EXPECT_NE(bus.stats().last_error.find("ghost"), std::string::npos) << bus.stats().last_error;
  EXPECT_NE(bus.stats().last_error.find("busy"), std::string::npos) << bus.stats().last_error;
}

}  // namespace
}  // namespace odonata::signal_service

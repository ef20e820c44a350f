// PlantNode over memq://: the messages in and out of odonata-plant, in one process. memq delivers
// within one LCM instance, so the test talks to the node through the node's own BusNode, and the
// node's handlers run when the test turns the Asio loop (Pump).
#include "plant_node.hpp"
#include "odonata/control_reply_t.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <vector>

#include "experiments/experiment_preset.hpp"
#include "experiments/sample_columns.hpp"
#include "messages/beat_state_message.hpp"
#include "messages/plant_state_message.hpp"
#include "messages/wing_command_message.hpp"
#include "pipeline/vehicle_setup.hpp"
#include "plant/output_signals.hpp"
#include "support/memq_bus.hpp"
#include "vehicle/attitude_hold.hpp"

namespace odonata::plant_service {
namespace {

using Mode = pipeline::PlantSession::Mode;

using testing::MemqOptions;

void Pump(bus::BusNode& bus, int ms = 5) { testing::Pump(bus, ms); }

odonata::wing_command_t Command(int64_t seq, const plant::CommandMatrix& c) {
  odonata::wing_command_t m{};
  m.seq = seq;
  m.t_s = 0.01 * static_cast<double>(seq);
  for (int w = 0; w < 4; ++w) {
    m.beta_rad[w] = c(w, 0);
    m.freq_hz[w] = c(w, 1);
    m.amp_rad[w] = c(w, 2);
    m.pitch_mean_rad[w] = c(w, 3);
    m.pitch_amp_rad[w] = c(w, 4);
    m.phase_rad[w] = c(w, 5);
  }
  m.source = "test";
  return m;
}

bool SameState(const odonata::plant_state_t& a, const odonata::plant_state_t& b) {
  for (const std::string& name : plant::StateSignalNames()) {
    const double x = *messages::StateField(a, name), y = *messages::StateField(b, name);
    if (std::memcmp(&x, &y, sizeof x) != 0) return false;
  }
  return a.seq == b.seq && a.command_seq == b.command_seq && a.t_s == b.t_s;
}

class PlantNodeTest : public ::testing::Test {
 protected:
  void Start(Mode mode, const std::string& preset = "roll") {
    bus_ = std::make_unique<bus::BusNode>(MemqOptions(kServiceName));
    // Subscribed before the node, so state 0 (published by its constructor) is seen too.
    bus_->Subscribe<odonata::plant_state_t>(bus_->channels().state,
                                            [this](const auto& m) { states_.push_back(m); });
    bus_->Subscribe<odonata::beat_state_t>(bus_->channels().beat_state,
                                           [this](const auto& m) { beats_.push_back(m); });
    node_ = std::make_unique<PlantNode>(*bus_, config_, mode, preset);
    trim_ = node_->session().setup().trim_command;
  }
  void Send(const odonata::wing_command_t& m) {
    bus_->Publish(bus_->channels().command, m);
    Pump(*bus_);
  }
  void Control(int8_t command, const std::string& target, const std::string& path = "",
               const std::string& sender = "odonata-control") {
    odonata::control_t c{};
    c.sender = sender;
    c.target = target;
    c.command = command;
    c.path = path;
    bus_->Publish(bus_->channels().control, c);
    Pump(*bus_);
  }

  plant::PlantConfig config_ = plant::DefaultPlantConfig();
  std::unique_ptr<bus::BusNode> bus_;
  std::unique_ptr<PlantNode> node_;
  std::vector<odonata::plant_state_t> states_;
  std::vector<odonata::beat_state_t> beats_;
  plant::CommandMatrix trim_;
};

// Bitwise equality, so -0.0 and 0.0 differ and NaN equals itself.
bool Same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// The beat averages and applied command of `m` are, bit for bit, those of the plant library's
// output `o` after applying `applied`.
void ExpectBeatState(const odonata::beat_state_t& m, const plant::PlantOutput& o,
                     const plant::CommandMatrix& applied, double trim_amp_rad) {
  EXPECT_TRUE(Same(m.t_s, o.time_s));
  EXPECT_TRUE(Same(m.window_s, o.beat.window_s));
  for (int i = 0; i < 3; ++i) {
    EXPECT_TRUE(Same(m.velocity_mps[i], o.beat.velocity_body_mps(i))) << i;
    EXPECT_TRUE(Same(m.rate_radps[i], o.beat.rate_body_radps(i))) << i;
  }
  EXPECT_TRUE(Same(m.attitude_rad[0], o.beat.roll_rad));
  EXPECT_TRUE(Same(m.attitude_rad[1], o.beat.pitch_rad));
  EXPECT_TRUE(Same(m.attitude_rad[2], o.beat.yaw_rad));
  EXPECT_TRUE(Same(m.fx_total_n, o.beat.force_x_n));
  EXPECT_TRUE(Same(m.fz_total_n, o.beat.force_z_n));
  for (int w = 0; w < 4; ++w) {
    EXPECT_TRUE(Same(m.applied_beta_rad[w], applied(w, plant::kStrokePlaneAngle))) << w;
    EXPECT_TRUE(Same(m.applied_freq_hz[w], applied(w, plant::kFlapFrequency))) << w;
    EXPECT_TRUE(Same(m.applied_amp_rad[w], applied(w, plant::kStrokeAmplitude))) << w;
    EXPECT_TRUE(Same(m.applied_pitch_mean_rad[w], applied(w, plant::kPitchMean))) << w;
    EXPECT_TRUE(Same(m.applied_pitch_amp_rad[w], applied(w, plant::kPitchAmplitude))) << w;
    EXPECT_TRUE(Same(m.applied_phase_rad[w], applied(w, plant::kPitchPhase))) << w;
  }
  const std::vector<double> u = vehicle::AppliedChannelValues(applied, trim_amp_rad);
  EXPECT_TRUE(Same(m.u_vertical_applied_rad, u[0]));
  EXPECT_TRUE(Same(m.u_roll_applied_rad, u[1]));
  EXPECT_TRUE(Same(m.u_pitch_applied_rad, u[2]));
  EXPECT_TRUE(Same(m.u_yaw_applied_rad, u[3]));
}

// Every DIMAV_STATE has a DIMAV_BEAT_STATE with the same seq and command_seq, holding the plant
// library's beat averages and the command applied in answer to command_seq, hold included: an
// independent DimavPlant flown with the same hold (odonata-sim's loop) gives the same bits.
TEST_F(PlantNodeTest, PublishesTheBeatStateBesideEveryStateWithTheSameSeq) {
  Start(Mode::kLockstep, "roll");
  const pipeline::VehicleSetup setup = node_->session().setup();
  ASSERT_TRUE(setup.attitude_hold);
  const experiments::ExperimentRun run = experiments::BuildExperimentRun(
      *experiments::FindPreset("roll"), experiments::Phase::kTrain, 2, 1.5, config_);
  const double trim_amp_rad = run.trim.amp_rad;

  plant::DimavPlant reference(config_);
  reference.Reset(setup.initial);
  Pump(*bus_);
  ASSERT_EQ(beats_.size(), 1u);
  EXPECT_EQ(beats_[0].seq, 0);
  EXPECT_EQ(beats_[0].command_seq, -1);
  EXPECT_EQ(beats_[0].attitude_hold, 1);
  ExpectBeatState(beats_[0], reference.output(), reference.applied_command(), trim_amp_rad);

  double hold_acted_rad = 0.0;
  for (std::size_t k = 0; k < run.commands.size(); ++k) {
    Send(Command(static_cast<int64_t>(k), run.commands[k]));
    const plant::CommandMatrix applied = reference.ClampToLimits(
        vehicle::ApplyAttitudeHold(setup.hold_gains, run.commands[k], reference.output()));
    ASSERT_EQ(reference.Step(applied), plant::StepStatus::kOk);
    ASSERT_EQ(beats_.size(), states_.size());
    const odonata::beat_state_t& b = beats_.back();
    ASSERT_EQ(b.seq, states_.back().seq);
    ASSERT_EQ(b.seq, static_cast<int64_t>(k) + 1);
    ASSERT_EQ(b.command_seq, states_.back().command_seq);
    EXPECT_EQ(b.t_s, states_.back().t_s);
    ExpectBeatState(b, reference.output(), applied, trim_amp_rad);
    ASSERT_TRUE(messages::AllFinite(b));
    hold_acted_rad =
        std::max(hold_acted_rad, std::fabs(b.u_roll_applied_rad - run.excitation_values[0][k]));
  }
  EXPECT_GT(hold_acted_rad, 1e-5);  // the applied roll channel is not the excitation

  // A resent command re-sends both messages, unchanged.
  const odonata::beat_state_t last = beats_.back();
  Send(Command(static_cast<int64_t>(run.commands.size()) - 1, run.commands.back()));
  ASSERT_EQ(beats_.size(), states_.size());
  EXPECT_EQ(beats_.back().seq, last.seq);
  EXPECT_TRUE(Same(beats_.back().velocity_mps[2], last.velocity_mps[2]));
  EXPECT_TRUE(Same(beats_.back().u_roll_applied_rad, last.u_roll_applied_rad));
}

TEST_F(PlantNodeTest, LockstepAnswersEachCommandOnceAndResendsWithoutStepping) {
  Start(Mode::kLockstep);
  Pump(*bus_);
  ASSERT_EQ(states_.size(), 1u);
  EXPECT_EQ(states_[0].seq, 0);
  EXPECT_EQ(states_[0].command_seq, -1);
  EXPECT_EQ(states_[0].position_m[2], pipeline::kDefaultStartAltitudeM);

  Send(Command(0, trim_));
  ASSERT_EQ(states_.size(), 2u);
  EXPECT_EQ(states_[1].seq, 1);
  EXPECT_EQ(states_[1].command_seq, 0);
  const double t1_s = node_->session().plant().output().time_s;

  Send(Command(0, trim_));  // the generator lost state 1 and resent command 0
  ASSERT_EQ(states_.size(), 3u);
  EXPECT_TRUE(SameState(states_[2], states_[1]));
  EXPECT_EQ(node_->session().plant().output().time_s, t1_s);  // no second step

  Send(Command(1, trim_));
  ASSERT_EQ(states_.size(), 4u);
  EXPECT_EQ(states_[3].seq, 2);
  EXPECT_EQ(states_[3].command_seq, 1);
  EXPECT_EQ(bus_->stats().dropped, 0);
  EXPECT_EQ(bus_->stats().gaps, 0);
}

TEST_F(PlantNodeTest, StaleNaNAndOutOfLimitCommandsAreDroppedAndCounted) {
  Start(Mode::kLockstep);
  Send(Command(0, trim_));
  Send(Command(1, trim_));
  const std::size_t before = states_.size();

  Send(Command(0, trim_));  // a resend of an applied one: its answer again, no step
  ASSERT_EQ(states_.size(), before + 1);
  EXPECT_EQ(states_.back().seq, 1);
  EXPECT_EQ(states_.back().command_seq, 0);
  odonata::wing_command_t nan = Command(2, trim_);
  nan.freq_hz[1] = std::numeric_limits<double>::quiet_NaN();
  Send(nan);
  odonata::wing_command_t inf_excitation = Command(2, trim_);
  inf_excitation.num_excitations = 1;
  inf_excitation.excitation_names = {"u_roll_rad"};
  inf_excitation.excitations = {std::numeric_limits<double>::infinity()};
  Send(inf_excitation);
  odonata::wing_command_t high = Command(2, trim_);
  high.beta_rad[3] = 1.0;  // limit ±30°
  Send(high);

  EXPECT_EQ(states_.size(), before + 1);  // none of these was answered
  EXPECT_EQ(bus_->stats().dropped, 3);
  EXPECT_EQ(node_->session().last().seq, 2);

  Send(Command(4, trim_));  // ahead of commands 2 and 3: held until they come
  EXPECT_EQ(states_.size(), before + 1);
  Send(Command(3, trim_));
  Send(Command(2, trim_));
  ASSERT_EQ(states_.size(), before + 4);
  EXPECT_EQ(states_.back().seq, 5);
  EXPECT_EQ(states_.back().command_seq, 4);
  EXPECT_EQ(bus_->stats().gaps, 0);
  for (const auto& s : states_) EXPECT_TRUE(messages::AllFinite(s));
}

TEST_F(PlantNodeTest, StateZeroRepeatsUntilTheFirstCommand) {
  Start(Mode::kLockstep);
  Pump(*bus_, 650);  // three periods of 200 ms (slack for a loaded machine)
  ASSERT_GE(states_.size(), 3u);
  for (const auto& s : states_) EXPECT_EQ(s.seq, 0);
  Send(Command(0, trim_));
  const std::size_t answered = states_.size();
  Pump(*bus_, 250);
  EXPECT_EQ(states_.size(), answered);  // quiet once commanded
}

TEST_F(PlantNodeTest, ResetToAnotherPresetAndShutdown) {
  Start(Mode::kLockstep, "roll");
  Send(Command(0, trim_));
  Send(Command(1, trim_));
  Control(odonata::control_t::RESET, "someone-else", "actuator_fz");  // not for us
  EXPECT_EQ(node_->session().last().seq, 2);

  states_.clear();
  Control(odonata::control_t::RESET, kServiceName, "actuator_fz");
  ASSERT_EQ(states_.size(), 1u);
  EXPECT_EQ(states_[0].seq, 0);
  EXPECT_EQ(states_[0].command_seq, -1);
  EXPECT_EQ(node_->session().setup().name, "actuator_fz");
  Send(Command(0, trim_));  // seq 0 is new again
  ASSERT_EQ(states_.size(), 2u);
  EXPECT_EQ(states_[1].seq, 1);
  EXPECT_EQ(states_[1].position_m[2], states_[0].position_m[2]);  // test stand: held

  Control(odonata::control_t::RESET, "", "no_such_preset");  // refused, counted
  EXPECT_EQ(bus_->stats().dropped, 1);
  EXPECT_EQ(node_->session().setup().name, "actuator_fz");
  // Reset and shutdown only from allowed senders: a stranger's are refused and counted.
  Send(Command(1, trim_));
  Control(odonata::control_t::RESET, "", "roll", "stranger");
  Control(odonata::control_t::SHUTDOWN, "", "", "");
  EXPECT_EQ(bus_->stats().dropped, 3);
  EXPECT_EQ(node_->session().setup().name, "actuator_fz");
  EXPECT_EQ(node_->session().last().seq, 2);
  EXPECT_FALSE(bus_->io().stopped());

  Control(odonata::control_t::RESET, "");  // empty path: the current set-up again
  EXPECT_EQ(states_.back().seq, 0);

  odonata::control_t c{};
  c.command = odonata::control_t::SHUTDOWN;
  c.sender = "odonata-signal";
  bus_->Publish(bus_->channels().control, c);
  bus_->After(std::chrono::seconds(3), [this] { bus_->Stop(99); });  // fence
  bus_->io().restart();
  EXPECT_EQ(bus_->Run(), 0);
}

// The plant answers what it acts on, rejects by name what is not for it (freeze), and stays
// silent when such a command goes to every service (it is the identifier's).
TEST_F(PlantNodeTest, AnswersItsCommandsAndRejectsOthersOnlyWhenNamed) {
  Start(Mode::kLockstep, "roll");
  std::vector<odonata::control_reply_t> replies;
  bus_->Subscribe<odonata::control_reply_t>(bus_->channels().control_reply,
                                            [&](const auto& r) { replies.push_back(r); });
  Control(odonata::control_t::RESET, kServiceName, "actuator_fz");
  ASSERT_EQ(replies.size(), 1u);
  EXPECT_TRUE(replies[0].accepted);
  EXPECT_NE(replies[0].reason.find("actuator_fz"), std::string::npos) << replies[0].reason;
  EXPECT_EQ(replies[0].service, kServiceName);

  Control(odonata::control_t::RESET, kServiceName, "no_such_preset");
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_FALSE(replies[1].accepted);
  EXPECT_NE(replies[1].reason.find("no_such_preset"), std::string::npos) << replies[1].reason;

  Control(odonata::control_t::FREEZE, "");  // for the identifier: not a word from the plant
  EXPECT_EQ(replies.size(), 2u);
  Control(odonata::control_t::FREEZE, kServiceName);
  ASSERT_EQ(replies.size(), 3u);
  EXPECT_FALSE(replies[2].accepted);
  EXPECT_NE(replies[2].reason.find("freeze"), std::string::npos) << replies[2].reason;

  Control(odonata::control_t::GET, "");
  ASSERT_EQ(replies.size(), 4u);
  EXPECT_TRUE(replies[3].accepted);
  ASSERT_GE(replies[3].num_params, 1);
  EXPECT_EQ(replies[3].names[0], "lockstep");
  EXPECT_EQ(replies[3].values[0], 1.0);
}

// odonata-control resends a command until it hears the answer: a resend (same sender, seq and
// utime) gets the first answer again and is not obeyed twice.
TEST_F(PlantNodeTest, AResentCommandIsAnsweredAgainNotObeyedAgain) {
  Start(Mode::kLockstep, "roll");
  std::vector<odonata::control_reply_t> replies;
  bus_->Subscribe<odonata::control_reply_t>(bus_->channels().control_reply,
                                            [&](const auto& r) { replies.push_back(r); });
  odonata::control_t c{};
  c.utime = bus::NowUtime();  // a live command (one from before the start is a replay's)
  c.seq = 4242;
  c.sender = "odonata-control";
  c.target = kServiceName;
  c.command = odonata::control_t::RESET;
  c.path = "actuator_fz";
  Send(Command(0, trim_));
  Send(Command(1, trim_));
  bus_->Publish(bus_->channels().control, c);
  Pump(*bus_);
  ASSERT_FALSE(states_.empty());
  EXPECT_EQ(states_.back().seq, 0);  // state 0 of the new set-up
  ASSERT_EQ(replies.size(), 1u);
  Send(Command(0, trim_));
  EXPECT_EQ(states_.back().seq, 1);
  const std::size_t states = states_.size();
  bus_->Publish(bus_->channels().control, c);  // the same message again
  Pump(*bus_);
  EXPECT_EQ(states_.size(), states) << "the resend reset the plant again";
  EXPECT_EQ(node_->session().last().seq, 1);
  ASSERT_EQ(replies.size(), 2u);
  EXPECT_EQ(replies[1].seq, replies[0].seq);  // the same answer, published again
  EXPECT_EQ(replies[1].reason, replies[0].reason);
  c.utime += 1;  // a new command (a new publish time) is obeyed
  bus_->Publish(bus_->channels().control, c);
  Pump(*bus_);
  EXPECT_EQ(states_.back().seq, 0);
  EXPECT_EQ(replies.size(), 3u);
}

TEST_F(PlantNodeTest, RealtimeTicksWithTrimThenTheNewestCommand) {
  Start(Mode::kRealtime);
  Pump(*bus_, 65);  // ≈ 6 ticks at 100 Hz
  ASSERT_GE(states_.size(), 3u);
  for (std::size_t i = 0; i < states_.size(); ++i) {
    EXPECT_EQ(states_[i].seq, static_cast<int64_t>(i));
    EXPECT_EQ(states_[i].command_seq, -1);
  }
  Send(Command(0, trim_));
  Send(Command(0, trim_));  // duplicate: dropped
  const std::size_t before = states_.size();
  Pump(*bus_, 35);
  ASSERT_GT(states_.size(), before);
  EXPECT_EQ(states_.back().command_seq, 0);
  EXPECT_EQ(states_.back().seq, static_cast<int64_t>(states_.size()) - 1);  // no gaps
  EXPECT_EQ(bus_->stats().dropped, 1);
}

}  // namespace
}  // namespace odonata::plant_service

// PlantSession: the sequence rules of both modes, and that stepping equals odonata-sim's
// per-sample order (hold on the pre-step output, clamp, step).
#include "pipeline/plant_session.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include "experiments/experiment_preset.hpp"
#include "pipeline/vehicle_setup.hpp"
#include "sequence/sequence_window.hpp"
#include "vehicle/attitude_hold.hpp"
#include "vehicle/command_limits.hpp"

namespace odonata::pipeline {
namespace {

using Mode = PlantSession::Mode;

bool SameBits(const plant::PlantOutput& a, const plant::PlantOutput& b) {
  const auto same = [](const double* x, const double* y, int n) {
    return std::memcmp(x, y, sizeof(double) * static_cast<std::size_t>(n)) == 0;
  };
  return same(a.velocity_body_mps.data(), b.velocity_body_mps.data(), 3) &&
         same(a.rate_body_radps.data(), b.rate_body_radps.data(), 3) &&
         same(&a.roll_rad, &b.roll_rad, 1) && same(&a.pitch_rad, &b.pitch_rad, 1) &&
         same(&a.yaw_rad, &b.yaw_rad, 1) && same(a.position_m.data(), b.position_m.data(), 3) &&
         same(a.force_x_n.data(), b.force_x_n.data(), 4) &&
         same(a.force_z_n.data(), b.force_z_n.data(), 4) && same(&a.time_s, &b.time_s, 1);
}

class PlantSessionTest : public ::testing::Test {
 protected:
  void SetUp() override {
    config_ = plant::DefaultPlantConfig();
    roll_ = PresetVehicleSetup(*experiments::FindPreset("roll"), config_);
  }
  plant::PlantConfig config_;
  VehicleSetup roll_;
};

TEST_F(PlantSessionTest, PresetSetupIsBuildExperimentRunsInitialCondition) {
  const auto run = experiments::BuildExperimentRun(*experiments::FindPreset("roll"),
                                                   experiments::Phase::kValidate, 9, 1.0, config_);
  EXPECT_TRUE(roll_.attitude_hold);
  EXPECT_FALSE(roll_.initial.clamped_body);
  EXPECT_EQ(roll_.initial.state.position_m, run.initial.state.position_m);
  EXPECT_EQ(roll_.initial.prior_command, run.initial.prior_command);
  EXPECT_EQ(roll_.trim_command, run.trim.command);
  const VehicleSetup fz = VehicleSetupByName("actuator_fz", config_);
  EXPECT_TRUE(fz.initial.clamped_body);
  EXPECT_FALSE(fz.attitude_hold);
  EXPECT_EQ(VehicleSetupByName("", config_).name, "default");
  EXPECT_THROW(VehicleSetupByName("rol", config_), std::invalid_argument);
}

TEST_F(PlantSessionTest, LockstepStepsExactlyAsOdonataSimDoes) {
  const auto run = experiments::BuildExperimentRun(*experiments::FindPreset("roll"),
                                                   experiments::Phase::kTrain, 3, 0.5, config_);
  PlantSession session(config_, Mode::kLockstep, roll_);
  EXPECT_EQ(session.last().seq, 0);
  EXPECT_EQ(session.last().command_seq, -1);
  // The reference is sim_runner.cpp's loop, written out.
  plant::DimavPlant reference(config_);
  reference.Reset(run.initial);
  ASSERT_TRUE(SameBits(session.last().output, reference.output()));
  for (std::size_t k = 0; k < run.commands.size(); ++k) {
    const CommandOutcome out = session.Submit(static_cast<int64_t>(k), run.commands[k]);
    ASSERT_EQ(out.verdict, CommandVerdict::kStepped) << k;
    ASSERT_EQ(out.publish.size(), 1u);
    reference.Step(reference.ClampToLimits(
        vehicle::ApplyAttitudeHold(run.hold_gains, run.commands[k], reference.output())));
    EXPECT_EQ(out.publish[0].seq, static_cast<int64_t>(k) + 1);
    EXPECT_EQ(out.publish[0].command_seq, static_cast<int64_t>(k));
    ASSERT_TRUE(SameBits(out.publish[0].output, reference.output())) << "sample " << k + 1;
  }
}

// A damage preset's validation set-up carries its damage, which the session flies exactly as
// odonata-sim does (the damaged command is stepped; the recorded applied command is the
// commanded one); the other phases and the bare name fly an intact vehicle.
TEST_F(PlantSessionTest, DamagePresetValidationFliesTheDamageAsOdonataSimDoes) {
  const experiments::ExperimentPreset& preset = *experiments::FindPreset("wing_damage");
  EXPECT_EQ(SetupName(preset, experiments::Phase::kValidate), "wing_damage@validate");
  EXPECT_EQ(SetupName(preset, experiments::Phase::kTrain), "wing_damage");
  EXPECT_EQ(SetupName(*experiments::FindPreset("roll"), experiments::Phase::kValidate), "roll");
  EXPECT_FALSE(std::isfinite(VehicleSetupByName("wing_damage", config_).damage.at_s));
  EXPECT_FALSE(std::isfinite(VehicleSetupByName("wing_damage@select", config_).damage.at_s));
  EXPECT_THROW(VehicleSetupByName("wing_damage@later", config_), std::invalid_argument);
  VehicleSetup damaged = VehicleSetupByName("wing_damage@validate", config_);
  ASSERT_DOUBLE_EQ(damaged.damage.at_s, 30.0);
  damaged.damage.at_s = 0.2;  // early, so a short run sees it

  auto run =
      experiments::BuildExperimentRun(preset, experiments::Phase::kValidate, 3, 0.5, config_);
  run.damage = damaged.damage;
  PlantSession session(config_, Mode::kLockstep, damaged);
  plant::DimavPlant reference(config_);
  reference.Reset(run.initial);
  plant::DimavPlant intact(config_);
  intact.Reset(run.initial);
  for (std::size_t k = 0; k < run.commands.size(); ++k) {
    const CommandOutcome out = session.Submit(static_cast<int64_t>(k), run.commands[k]);
    ASSERT_EQ(out.publish.size(), 1u);
    const plant::CommandMatrix applied = reference.ClampToLimits(run.commands[k]);
    reference.Step(run.damage.Apply(applied, static_cast<double>(k) * run.sample_period_s));
    intact.Step(applied);
    ASSERT_TRUE(SameBits(out.publish[0].output, reference.output())) << "sample " << k + 1;
    EXPECT_TRUE(out.publish[0].applied_command == applied);
  }
  // The damaged wing lifts less than the intact vehicle's by the end of the run.
  EXPECT_LT(session.last().output.force_z_n(0), 0.8 * intact.output().force_z_n(0));
}

TEST_F(PlantSessionTest, LockstepRepeatStaleGapAndRejection) {
  PlantSession session(config_, Mode::kLockstep, roll_);
  const plant::CommandMatrix trim = roll_.trim_command;
  ASSERT_EQ(session.Submit(0, trim).verdict, CommandVerdict::kStepped);
  const PlantSample after0 = session.last();

  // A resend: the same answer, and the plant did not move.
  const CommandOutcome again = session.Submit(0, trim);
  EXPECT_EQ(again.verdict, CommandVerdict::kRepeated);
  ASSERT_EQ(again.publish.size(), 1u);
  EXPECT_EQ(again.publish[0].seq, 1);
  EXPECT_TRUE(SameBits(again.publish[0].output, after0.output));
  EXPECT_EQ(session.plant().output().time_s, after0.output.time_s);

  // An older one is answered from the history too, as long as it is kept.
  ASSERT_EQ(session.Submit(1, trim).verdict, CommandVerdict::kStepped);
  const CommandOutcome older = session.Submit(0, trim);
  EXPECT_EQ(older.verdict, CommandVerdict::kRepeated);
  ASSERT_EQ(older.publish.size(), 1u);
  EXPECT_EQ(older.publish[0].seq, 1);
  EXPECT_EQ(older.publish[0].command_seq, 0);
  EXPECT_EQ(session.last().seq, 2);
  for (int64_t k = 2; k < 2 + static_cast<int64_t>(PlantSession::kAnswerHistory); ++k)
    ASSERT_EQ(session.Submit(k, trim).verdict, CommandVerdict::kStepped);
  const CommandOutcome stale = session.Submit(1, trim);
  EXPECT_EQ(stale.verdict, CommandVerdict::kStale);
  EXPECT_TRUE(stale.publish.empty());
  const int64_t next = session.last().seq;  // the next command expected

  plant::CommandMatrix nan = trim;
  nan(2, plant::kFlapFrequency) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(session.Submit(next, nan).verdict, CommandVerdict::kRejected);
  plant::CommandMatrix high = trim;
  high(1, plant::kStrokeAmplitude) = config_.limits.max(plant::kStrokeAmplitude) + 0.01;
  const CommandOutcome rejected = session.Submit(next, high);
  EXPECT_EQ(rejected.verdict, CommandVerdict::kRejected);
  EXPECT_NE(rejected.problem.find("w2_amp_rad"), std::string::npos) << rejected.problem;
  EXPECT_EQ(session.Submit(-3, trim).verdict, CommandVerdict::kRejected);
  EXPECT_EQ(session.last().seq, next);  // nothing of the above stepped
}

// Commands that overtake a missing one wait for it, so a window of commands in flight gives the
// run one at a time gives, bit for bit.
TEST_F(PlantSessionTest, LockstepHoldsCommandsAheadOfAMissingOne) {
  PlantSession one_by_one(config_, Mode::kLockstep, roll_);
  PlantSession windowed(config_, Mode::kLockstep, roll_);
  std::vector<plant::CommandMatrix> commands;
  for (int k = 0; k < 6; ++k) {
    plant::CommandMatrix c = roll_.trim_command;
    c(0, plant::kFlapFrequency) += 0.5 * k;
    commands.push_back(c);
    one_by_one.Submit(k, c);
  }
  ASSERT_EQ(windowed.Submit(0, commands[0]).verdict, CommandVerdict::kStepped);
  for (int k : {2, 3, 5}) {
    const CommandOutcome held = windowed.Submit(k, commands[k]);
    EXPECT_EQ(held.verdict, CommandVerdict::kHeld) << k;
    EXPECT_TRUE(held.publish.empty());
  }
  EXPECT_EQ(windowed.Submit(3, commands[3]).verdict, CommandVerdict::kHeld);  // resent
  EXPECT_EQ(windowed.last().seq, 1);
  const CommandOutcome released = windowed.Submit(1, commands[1]);
  EXPECT_EQ(released.verdict, CommandVerdict::kStepped);
  ASSERT_EQ(released.publish.size(), 3u);  // 1, then the held 2 and 3; 5 waits for 4
  EXPECT_EQ(released.publish[2].seq, 4);
  EXPECT_EQ(released.publish[2].command_seq, 3);
  ASSERT_EQ(windowed.Submit(4, commands[4]).publish.size(), 2u);
  EXPECT_EQ(windowed.last().seq, 6);
  EXPECT_TRUE(SameBits(windowed.last().output, one_by_one.last().output));
}

TEST_F(PlantSessionTest, LockstepStepsOverAGapOnlyWhenTooManyCommandsWait) {
  PlantSession session(config_, Mode::kLockstep, roll_);
  const plant::CommandMatrix trim = roll_.trim_command;
  ASSERT_EQ(session.Submit(0, trim).verdict, CommandVerdict::kStepped);
  const int64_t first_held = 4;  // 1, 2, 3 never come
  for (int64_t k = first_held;
       k < first_held + static_cast<int64_t>(PlantSession::kMaxHeldCommands); ++k)
    ASSERT_EQ(session.Submit(k, trim).verdict, CommandVerdict::kHeld) << k;
  const CommandOutcome gap =
      session.Submit(first_held + static_cast<int64_t>(PlantSession::kMaxHeldCommands), trim);
  EXPECT_EQ(gap.verdict, CommandVerdict::kGap);
  EXPECT_EQ(gap.missing, 3);
  ASSERT_EQ(gap.publish.size(), PlantSession::kMaxHeldCommands + 1);
  EXPECT_EQ(gap.publish[0].seq, first_held + 1);
  EXPECT_EQ(gap.publish[0].command_seq, first_held);
  EXPECT_DOUBLE_EQ(gap.publish[0].output.time_s, 2 * session.plant().sample_period_s());
}

TEST_F(PlantSessionTest, ASeqThatLeapsAheadIsRejectedAndDoesNotStallTheRun) {
  for (const Mode mode : {Mode::kLockstep, Mode::kRealtime}) {
    PlantSession session(config_, mode, roll_);
    const plant::CommandMatrix trim = roll_.trim_command;
    // Before any command (a forged first one) and after some: both would make every genuine
    // command after them stale.
    const CommandOutcome first = session.Submit(kMaxSeqJump + 1, trim);
    EXPECT_EQ(first.verdict, CommandVerdict::kRejected);
    EXPECT_NE(first.problem.find("leaps"), std::string::npos) << first.problem;
    EXPECT_FALSE(session.commanded());
    EXPECT_NE(session.Submit(0, trim).verdict, CommandVerdict::kRejected);
    EXPECT_EQ(session.Submit(int64_t{1} << 40, trim).verdict, CommandVerdict::kRejected);
    EXPECT_NE(session.Submit(1, trim).verdict, CommandVerdict::kRejected);
    // A long gap within the window is held until a second command confirms it.
    const CommandOutcome held = session.Submit(kMaxSeqJump, trim);
    EXPECT_EQ(held.verdict, CommandVerdict::kRejected);
    EXPECT_NE(held.problem.find("held until"), std::string::npos) << held.problem;
    EXPECT_NE(session.Submit(kMaxSeqJump + 1, trim).verdict, CommandVerdict::kRejected);
  }
}

// A forged command a little ahead (+999), resent again and again, is held, never confirmed, and
// the genuine commands after it go on stepping.
TEST_F(PlantSessionTest, AForgedLeapCannotMakeGenuineCommandsStale) {
  PlantSession session(config_, Mode::kLockstep, roll_);
  const plant::CommandMatrix trim = roll_.trim_command;
  for (int64_t k = 0; k < 5; ++k)
    ASSERT_EQ(session.Submit(k, trim).verdict, CommandVerdict::kStepped);
  EXPECT_EQ(session.Submit(4 + 999, trim).verdict, CommandVerdict::kRejected);
  for (int64_t k = 5; k < 10; ++k) {
    EXPECT_EQ(session.Submit(k, trim).verdict, CommandVerdict::kStepped) << k;
    EXPECT_EQ(session.Submit(4 + 999, trim).verdict, CommandVerdict::kRejected) << k;
  }
  EXPECT_EQ(session.last().seq, 10);
  // Within kConfirmLeap it is held, and the genuine commands before it step on.
  EXPECT_EQ(session.Submit(9 + kConfirmLeap, trim).verdict, CommandVerdict::kHeld);
  EXPECT_EQ(session.Submit(10, trim).verdict, CommandVerdict::kStepped);
}

TEST(LeapGuard, HoldsALongLeapUntilTheNextMessageConfirmsIt) {
  LeapGuard g;
  EXPECT_EQ(g.Check(900000, -1), LeapGuard::Verdict::kAccept);  // nothing to compare with yet
  EXPECT_EQ(g.Check(10, 5), LeapGuard::Verdict::kAccept);
  EXPECT_EQ(g.Check(5 + kConfirmLeap, 5), LeapGuard::Verdict::kAccept);
  EXPECT_EQ(g.Check(900000, 5), LeapGuard::Verdict::kHold);
  EXPECT_EQ(g.Check(6, 5), LeapGuard::Verdict::kAccept);       // genuine traffic goes on
  EXPECT_EQ(g.Check(900001, 6), LeapGuard::Verdict::kAccept);  // continued: a real gap
  EXPECT_EQ(g.Check(500000, 6), LeapGuard::Verdict::kHold);
  EXPECT_EQ(g.Check(500000, 6), LeapGuard::Verdict::kHold);  // resent: still not confirmed
  EXPECT_EQ(g.Check(-1, 6), LeapGuard::Verdict::kReject);
  EXPECT_EQ(g.Check(7 + kMaxSeqJump, 6), LeapGuard::Verdict::kReject);
}

TEST(SequenceWindow, BoundsTheJumpFromTheNewest) {
  EXPECT_TRUE(SeqWithinWindow(0, -1));
  EXPECT_TRUE(SeqWithinWindow(kMaxSeqJump - 1, -1));
  EXPECT_FALSE(SeqWithinWindow(kMaxSeqJump, -1));
  EXPECT_FALSE(SeqWithinWindow(-1, 5));
  EXPECT_TRUE(SeqWithinWindow(3, 5));  // older: the receiver's own rules decide
  EXPECT_TRUE(SeqWithinWindow(5 + kMaxSeqJump, 5));
  EXPECT_FALSE(SeqWithinWindow(6 + kMaxSeqJump, 5));
}

TEST_F(PlantSessionTest, ResetRestartsTheSequenceAtCommandZero) {
  PlantSession session(config_, Mode::kLockstep, roll_);
  const PlantSample initial = session.last();
  for (int64_t k = 0; k < 4; ++k) session.Submit(k, roll_.trim_command);
  const PlantSample& zero = session.Reset(roll_);
  EXPECT_EQ(zero.seq, 0);
  EXPECT_EQ(zero.command_seq, -1);
  EXPECT_TRUE(SameBits(zero.output, initial.output));
  EXPECT_FALSE(session.commanded());
  EXPECT_EQ(session.Submit(0, roll_.trim_command).verdict, CommandVerdict::kStepped);

  const VehicleSetup stand = VehicleSetupByName("actuator_fz", config_);
  session.Reset(stand);
  EXPECT_EQ(session.setup().name, "actuator_fz");
  // Command 0 comes first after a reset: a later one overtaking it waits, and the plant stays
  // uncommanded (so it goes on announcing its state 0).
  EXPECT_EQ(session.Submit(1, stand.trim_command).verdict, CommandVerdict::kHeld);
  EXPECT_FALSE(session.commanded());
  const CommandOutcome first = session.Submit(0, stand.trim_command);
  EXPECT_EQ(first.verdict, CommandVerdict::kStepped);
  EXPECT_EQ(first.missing, 0);
  ASSERT_EQ(first.publish.size(), 2u);
  EXPECT_EQ(first.publish[1].seq, 2);
  // Clamped test stand: the body does not move.
  EXPECT_EQ(first.publish[1].output.position_m, stand.initial.state.position_m);
}

TEST_F(PlantSessionTest, RealtimeHoldsTheNewestCommandFromTrim) {
  PlantSession session(config_, Mode::kRealtime, roll_);
  PlantSession reference(config_, Mode::kLockstep, roll_);
  const PlantSample& s1 = session.Tick();
  EXPECT_EQ(s1.seq, 1);
  EXPECT_EQ(s1.command_seq, -1);  // hover trim before any command
  reference.Submit(0, roll_.trim_command);
  EXPECT_TRUE(SameBits(s1.output, reference.last().output));

  plant::CommandMatrix c = roll_.trim_command;
  c(0, plant::kStrokeAmplitude) += 0.01;
  EXPECT_EQ(session.Submit(0, c).verdict, CommandVerdict::kAccepted);
  EXPECT_EQ(session.Submit(0, c).verdict, CommandVerdict::kStale);  // duplicate
  const CommandOutcome jump = session.Submit(4, c);
  EXPECT_EQ(jump.verdict, CommandVerdict::kAccepted);
  EXPECT_EQ(jump.missing, 3);
  EXPECT_TRUE(jump.publish.empty());
  EXPECT_EQ(session.Submit(2, c).verdict, CommandVerdict::kStale);
  for (int i = 0; i < 3; ++i) {  // zero-order hold: the same command every tick
    const PlantSample& s = session.Tick();
    EXPECT_EQ(s.seq, 2 + i);
    EXPECT_EQ(s.command_seq, 4);
    reference.Submit(1 + i, c);
    EXPECT_TRUE(SameBits(s.output, reference.last().output));
  }
}

// A late tick lets two commands arrive in one period (the first is never applied); a stalled
// sender lets one command be applied at several ticks. Both are reported when the next command
// replaces it, so a loaded machine's degradation is counted exactly.
TEST_F(PlantSessionTest, RealtimeReportsSkippedAndRepeatedCommands) {
  PlantSession session(config_, Mode::kRealtime, roll_);
  const plant::CommandMatrix c = roll_.trim_command;
  session.Tick();  // hover trim: no command to account for
  const CommandOutcome first = session.Submit(0, c);
  EXPECT_FALSE(first.superseded_unapplied);
  EXPECT_EQ(first.extra_applications, 0);
  EXPECT_EQ(session.Tick().command_seq, 0);
  const CommandOutcome once = session.Submit(1, c);  // 0 was applied exactly once
  EXPECT_FALSE(once.superseded_unapplied);
  EXPECT_EQ(once.extra_applications, 0);
  const CommandOutcome skip = session.Submit(2, c);  // 1 was never applied
  EXPECT_TRUE(skip.superseded_unapplied);
  EXPECT_EQ(skip.extra_applications, 0);
  for (int i = 0; i < 3; ++i) EXPECT_EQ(session.Tick().command_seq, 2);
  const CommandOutcome repeat = session.Submit(5, c);  // 2 applied three times; 3, 4 lost
  EXPECT_FALSE(repeat.superseded_unapplied);
  EXPECT_EQ(repeat.extra_applications, 2);
  EXPECT_EQ(repeat.missing, 2);
  // A reset forgets the held command: the next one replaces nothing.
  session.Reset(roll_);
  const CommandOutcome after_reset = session.Submit(0, c);
  EXPECT_FALSE(after_reset.superseded_unapplied);
  EXPECT_EQ(after_reset.extra_applications, 0);
}

TEST_F(PlantSessionTest, DivergenceStopsWithoutNaN) {
  plant::PlantConfig config = config_;
  config.divergence.max_tilt_rad = 0.05;  // an easy divergence
  VehicleSetup free = DefaultVehicleSetup(config);
  PlantSession session(config, Mode::kLockstep, free);
  plant::CommandMatrix roll = free.trim_command;
  roll(0, plant::kStrokeAmplitude) += 0.3;
  roll(1, plant::kStrokeAmplitude) += 0.3;
  bool diverged = false;
  for (int64_t k = 0; k < 300 && !diverged; ++k) {
    const CommandOutcome out = session.Submit(k, roll);
    ASSERT_EQ(out.publish.size(), 1u);
    EXPECT_TRUE(std::isfinite(out.publish[0].output.roll_rad));
    diverged = out.publish[0].status == SampleStatus::kDiverged;
  }
  EXPECT_TRUE(diverged);
  EXPECT_FALSE(session.plant().divergence_message().empty());
}

TEST(CommandLimits, ListsEveryProblem) {
  const plant::PlantConfig config = plant::DefaultPlantConfig();
  plant::CommandMatrix c = plant::UniformCommand(config.nominal_command);
  EXPECT_EQ(vehicle::CommandLimitProblems(c, config.limits), "");
  c(0, plant::kFlapFrequency) = 9.0;
  c(3, plant::kPitchPhase) = std::numeric_limits<double>::infinity();
  const std::string p = vehicle::CommandLimitProblems(c, config.limits);
  EXPECT_NE(p.find("w1_freq_hz = 9"), std::string::npos) << p;
  EXPECT_NE(p.find("w4_phase_rad is not finite"), std::string::npos) << p;
}

}  // namespace
}  // namespace odonata::pipeline

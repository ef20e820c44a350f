// The signals of telemetry logs: names as MAVLink users write them (array elements, senders), times
// in seconds from the log's first record, uint8_t fields held, times going back dropped, and
// names that are no signal answered with why and the nearest.
#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"
#include "mavlink_test_support.hpp"

namespace odonata::mavlink {
namespace {

using test_support::AttitudeFrame;
using test_support::kT0Us;
using test_support::TlogWriter;
using timeseries::Interpolation;

TlogFile ParseFlight() { return Parse(test_support::SmallFlightTlog().bytes(), "flight.tlog"); }

std::map<std::string, SignalInfo> TlogSignalsByName(const TlogFile& f) {
  std::map<std::string, SignalInfo> out;
  for (const SignalInfo& s : ListSignals(f)) out.emplace(s.name, s);
  return out;
}

// What Extract says about `name`; "" when it is a signal.
std::string TlogExtractError(const TlogFile& f, const std::string& name) {
  try {
    (void)Extract(f, name);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

void ExpectSamples(const timeseries::TimedSignal& s, const std::vector<double>& t_s,
                   const std::vector<double>& values) {
  ASSERT_EQ(s.t_s.size(), t_s.size()) << s.name;
  ASSERT_EQ(s.values.size(), values.size()) << s.name;
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    EXPECT_EQ(s.t_s[i], t_s[i]) << s.name << " sample " << i;  // µs / 1e6: rounded once
    EXPECT_EQ(s.values[i], values[i]) << s.name << " sample " << i;
  }
}

// A log of ACTUATOR_OUTPUT_STATUS at 50 Hz, 4 frames.
TlogFile ActuatorLog() {
  TlogWriter w;
  for (int i = 0; i < 4; ++i) {
    test_support::FrameSpec spec;
    spec.msgid = 375;
    spec.seq = static_cast<std::uint8_t>(i);
    spec.payload = test_support::ActuatorPayload(static_cast<std::uint64_t>(i) * 20'000,
                                                 {0.1f, 0.25f * static_cast<float>(i), -1.0f});
    w.Record(kT0Us + static_cast<std::uint64_t>(i) * 20'000, test_support::EncodeFrame(spec));
  }
  return Parse(w.bytes(), "actuators.tlog");
}

TEST(TlogSignals, NamedAsMavlinkUsersWriteThem) {
  const TlogFile f = ParseFlight();
  std::vector<std::string> names;
  for (const SignalInfo& s : ListSignals(f)) names.push_back(s.name);
  // ATTITUDE (7 fields), HEARTBEAT of its main sender (6), of the ground station (6),
  // SERVO_OUTPUT_RAW (time_usec, port, 16 servos): XML order within each.
  ASSERT_EQ(names.size(), 37u);
  EXPECT_EQ(names[0], "ATTITUDE.time_boot_ms");
  EXPECT_EQ(names[5], "ATTITUDE.pitchspeed");
  EXPECT_EQ(names[7], "HEARTBEAT.type");
  EXPECT_EQ(names[10], "HEARTBEAT.custom_mode");
  EXPECT_EQ(names[13], "HEARTBEAT@255:190.type");
  EXPECT_EQ(names[19], "SERVO_OUTPUT_RAW.time_usec");
  EXPECT_EQ(names[20], "SERVO_OUTPUT_RAW.port");
  EXPECT_EQ(names[23], "SERVO_OUTPUT_RAW.servo3_raw");
  EXPECT_EQ(names[36], "SERVO_OUTPUT_RAW.servo16_raw");

  const auto signals = TlogSignalsByName(f);
  const SignalInfo& pitchspeed = signals.at("ATTITUDE.pitchspeed");
  EXPECT_EQ(pitchspeed.message, "ATTITUDE");
  EXPECT_EQ(pitchspeed.field, "pitchspeed");
  EXPECT_EQ(pitchspeed.type, "float");
  EXPECT_EQ(pitchspeed.sysid, 1);
  EXPECT_EQ(pitchspeed.compid, 1);
  EXPECT_EQ(pitchspeed.samples, 5u);
  EXPECT_EQ(pitchspeed.out_of_order, 0u);
  EXPECT_NEAR(pitchspeed.median_rate_hz, 10.0, 1e-9);
  EXPECT_EQ(pitchspeed.interpolation, Interpolation::kLinear);
  EXPECT_EQ(signals.at("HEARTBEAT.base_mode").interpolation, Interpolation::kHold);  // uint8_t
  EXPECT_EQ(signals.at("HEARTBEAT.custom_mode").interpolation, Interpolation::kLinear);
  EXPECT_EQ(signals.at("HEARTBEAT.custom_mode").type, "uint32_t");
  EXPECT_EQ(signals.at("HEARTBEAT@255:190.type").sysid, 255);
  EXPECT_EQ(signals.at("HEARTBEAT@255:190.type").compid, 190);
  EXPECT_EQ(signals.at("HEARTBEAT@255:190.type").samples, 2u);
  EXPECT_EQ(signals.count("HEARTBEAT@1:1.type"), 0u);  // an alias, not listed
  EXPECT_EQ(signals.at("SERVO_OUTPUT_RAW.servo3_raw").samples, 3u);
  EXPECT_NEAR(signals.at("SERVO_OUTPUT_RAW.servo3_raw").median_rate_hz, 5.0, 1e-9);
}

TEST(TlogSignals, ValuesAndTimesFromTheLogsFirstRecord) {
  const TlogFile f = ParseFlight();
  std::vector<double> pitch;
  for (int i = 0; i < 5; ++i) pitch.push_back(static_cast<double>(0.01f * static_cast<float>(i)));
  const std::vector<double> attitude_t_s = {0.0, 0.1, 0.2, 0.3, 0.4};
  ExpectSamples(Extract(f, "ATTITUDE.pitch"), attitude_t_s, pitch);
  ExpectSamples(Extract(f, "ATTITUDE.pitchspeed"), attitude_t_s, {-0.5, 0.5, 1.5, 2.5, 3.5});
  ExpectSamples(Extract(f, "ATTITUDE.yawspeed"), attitude_t_s, {0, 0, 0, 0, 0});  // cut, put back
  // The main sender's "@" name is the plain name's alias; the signal is named as asked.
  const timeseries::TimedSignal alias = Extract(f, "ATTITUDE@1:1.pitch");
  EXPECT_EQ(alias.name, "ATTITUDE@1:1.pitch");
  ExpectSamples(alias, attitude_t_s, pitch);

  const std::vector<double> servo_t_s = {0.002, 0.202, 0.402};
  ExpectSamples(Extract(f, "SERVO_OUTPUT_RAW.servo3_raw"), servo_t_s, {1501, 1521, 1541});
  ExpectSamples(Extract(f, "SERVO_OUTPUT_RAW.servo12_raw"), servo_t_s, {1100, 1100, 0});

  const timeseries::TimedSignal base_mode = Extract(f, "HEARTBEAT.base_mode");
  EXPECT_EQ(base_mode.interpolation, Interpolation::kHold);
  ExpectSamples(base_mode, {0.003, 0.203, 0.403}, {81, 209, 209});
  ExpectSamples(Extract(f, "HEARTBEAT@255:190.type"), {0.105, 0.305}, {6, 6});
}

TEST(TlogSignals, ArrayElementsAreSignals) {
  const TlogFile f = ActuatorLog();
  const auto signals = TlogSignalsByName(f);
  EXPECT_EQ(signals.size(), 2u + 32u);  // time_usec, active, actuator[0..31]
  EXPECT_EQ(signals.count("ACTUATOR_OUTPUT_STATUS.actuator[0]"), 1u);
  EXPECT_EQ(signals.count("ACTUATOR_OUTPUT_STATUS.actuator[31]"), 1u);
  EXPECT_EQ(signals.at("ACTUATOR_OUTPUT_STATUS.actuator[1]").field, "actuator[1]");
  EXPECT_NEAR(signals.at("ACTUATOR_OUTPUT_STATUS.actuator[1]").median_rate_hz, 50.0, 1e-9);
  ExpectSamples(Extract(f, "ACTUATOR_OUTPUT_STATUS.actuator[1]"), {0.0, 0.02, 0.04, 0.06},
                {0.0, 0.25, 0.5, 0.75});
  ExpectSamples(Extract(f, "ACTUATOR_OUTPUT_STATUS.actuator[2]"), {0.0, 0.02, 0.04, 0.06},
                {-1, -1, -1, -1});
  EXPECT_NE(TlogExtractError(f, "ACTUATOR_OUTPUT_STATUS.actuator")
                .find("('actuator' has elements actuator[0] to actuator[31])"),
            std::string::npos);
}

TEST(TlogSignals, TimesGoingBackAreDroppedAndTimesCountFromTheFirstRecord) {
  TlogWriter w;
  test_support::FrameSpec heartbeat;
  heartbeat.msgid = 0;
  heartbeat.payload = test_support::HeartbeatPayload(0, 2, 81);
  w.Record(kT0Us + 100'000, test_support::EncodeFrame(heartbeat));  // the log's first record
  w.Record(kT0Us, AttitudeFrame(1, 1000, 0.0f, 1.0f));
  w.Record(kT0Us + 200'000, AttitudeFrame(2, 1200, 0.0f, 2.0f));
  w.Record(kT0Us + 150'000, AttitudeFrame(3, 1150, 0.0f, 3.0f));  // earlier than the one before
  w.Record(kT0Us + 300'000, AttitudeFrame(4, 1300, 0.0f, 4.0f));
  const TlogFile f = Parse(w.bytes(), "back.tlog");
  const timeseries::TimedSignal s = Extract(f, "ATTITUDE.pitchspeed");
  ExpectSamples(s, {-0.1, 0.1, 0.2}, {1.0, 2.0, 4.0});
  const SignalInfo info = TlogSignalsByName(f).at("ATTITUDE.pitchspeed");
  EXPECT_EQ(info.samples, 3u);
  EXPECT_EQ(info.out_of_order, 1u);
}

TEST(TlogSignals, ANameThatIsNoSignalIsAnsweredWithWhyAndTheNearest) {
  const TlogFile f = ParseFlight();
  const std::string typo = TlogExtractError(f, "ATTITUDE.pitchsped");
  EXPECT_NE(typo.find("no signal 'ATTITUDE.pitchsped' in flight.tlog"), std::string::npos) << typo;
  EXPECT_NE(typo.find("nearest: ATTITUDE.pitchspeed"), std::string::npos) << typo;
  EXPECT_NE(TlogExtractError(f, "AHRS2.roll")
                .find("'AHRS2' is no MAVLink message this reader decodes (it decodes "
                      "ACTUATOR_OUTPUT_STATUS, ATTITUDE,"),
            std::string::npos);
  EXPECT_NE(TlogExtractError(f, "HIGHRES_IMU.xgyro").find("(the log has no HIGHRES_IMU frames)"),
            std::string::npos);
  const std::string sender = TlogExtractError(f, "ATTITUDE@2:1.pitch");
  EXPECT_NE(sender.find("the log has no ATTITUDE frames from '2:1'"), std::string::npos) << sender;
  EXPECT_NE(sender.find("ATTITUDE came from 1:1"), std::string::npos) << sender;
  EXPECT_NE(TlogExtractError(f, "HEARTBEAT@1:1.nope").find("nearest: "), std::string::npos);
  EXPECT_NE(TlogExtractError(f, "ATTITUDE.pitch[0]").find("'pitch' is one value, no array"),
            std::string::npos);
  EXPECT_NE(TlogExtractError(f, "pitchspeed").find("signals are named MESSAGE.field"),
            std::string::npos);
  EXPECT_EQ(TlogExtractError(f, "HEARTBEAT@1:1.type"), "");
  EXPECT_EQ(TlogExtractError(f, "HEARTBEAT@255:190.type"), "");

  // A log with frames of unknown messages only has no signals.
  TlogWriter w;
  w.Record(kT0Us, test_support::UnknownFrame(0));
  const TlogFile unknown = Parse(w.bytes(), "unknown.tlog");
  EXPECT_TRUE(ListSignals(unknown).empty());
  EXPECT_NE(TlogExtractError(unknown, "ATTITUDE.pitch").find("it has no signals"),
            std::string::npos);
}

}  // namespace
}  // namespace odonata::mavlink

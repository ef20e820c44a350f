// A real telemetry log (shared/mavlink/ardusub_small.tlog: an ArduSub vehicle's link as its ground
// station recorded it, 263 s, MAVLink 2): message counts against an independent walk of the record
// headers, every ATTITUDE frame's checksum valid, values against numbers decoded apart from this
// reader (tlog_values_test.py, Python's struct module on the same bytes), the frame decoder fed
// the bare frames, and cuts and flipped bytes that never crash. tests/mavlink/CMakeLists.txt
// defines ODONATA_MAVLINK_DIR when the folder is there; the tests are skipped without it.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"

namespace odonata::mavlink {
namespace {

#ifdef ODONATA_MAVLINK_DIR

const std::string kArdusubTlogPath = std::string(ODONATA_MAVLINK_DIR) + "/ardusub_small.tlog";

// From tests/mavlink/tlog_values_test.py: an independent Python struct decoder of the same file
// (its --check compares these arrays with what it decodes). The first two ATTITUDE and
// SERVO_OUTPUT_RAW frames; times in seconds from the first record.
constexpr double kAttitudeTimeS[] = {0.438, 0.439};
constexpr double kAttitudeTimeBootMs[] = {689235.0, 689335.0};
constexpr double kAttitudeRoll[] = {-0.024300388991832733, -0.026810456067323685};
constexpr double kAttitudePitch[] = {0.02468784712255001, 0.025207003578543663};
constexpr double kAttitudeYaw[] = {-2.3479995727539062, -2.348109483718872};
constexpr double kAttitudeRollspeed[] = {-0.023370306938886642, -0.025613369420170784};
constexpr double kAttitudePitchspeed[] = {0.010745608247816563, 0.002547982381656766};
constexpr double kAttitudeYawspeed[] = {-0.0006981943151913583, 0.0005120348650962114};
constexpr double kServoOutputRawTimeS[] = {0.0, 0.445};
constexpr double kServoOutputRawTimeUsec[] = {689175102.0, 689675242.0};
constexpr double kServoOutputRawServo1Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo2Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo3Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo4Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo5Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo6Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo7Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawServo8Raw[] = {1500.0, 1500.0};
constexpr double kServoOutputRawPort[] = {0.0, 0.0};
constexpr double kServoOutputRawServo9Raw[] = {0.0, 0.0};
constexpr double kServoOutputRawServo10Raw[] = {0.0, 0.0};
constexpr double kServoOutputRawServo11Raw[] = {0.0, 0.0};
constexpr double kServoOutputRawServo12Raw[] = {1100.0, 1100.0};
constexpr double kServoOutputRawServo13Raw[] = {1100.0, 1100.0};
constexpr double kServoOutputRawServo14Raw[] = {0.0, 0.0};
constexpr double kServoOutputRawServo15Raw[] = {0.0, 0.0};
constexpr double kServoOutputRawServo16Raw[] = {1500.0, 1500.0};

std::string TlogFileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The least a reader must do, written apart from the one under test: each record's length from
// its frame's header (MAVLink 2: length byte at 9, incompat flags at 10, message id at 15..17;
// MAVLink 1: length at 9, id at 13), until a record does not fit or starts no frame.
struct TlogHeaderWalk {
  std::map<std::uint32_t, std::size_t> by_id;
  std::size_t total = 0;
  std::size_t v1 = 0;
  std::size_t end = 0;  // where the walk stopped: the end, or the start of a cut record
  std::vector<std::pair<std::size_t, std::size_t>> frames;  // offset and size of each frame
};

TlogHeaderWalk WalkTlogHeaders(const std::string& b) {
  TlogHeaderWalk w;
  const auto u8 = [&b](std::size_t i) {
    return static_cast<std::uint32_t>(static_cast<unsigned char>(b[i]));
  };
  std::size_t pos = 0;
  while (pos + 8 + 6 <= b.size()) {
    const std::uint32_t start = u8(pos + 8);
    std::size_t size = 0;
    std::uint32_t id = 0;
    if (start == 0xFD && pos + 8 + 10 <= b.size()) {
      size = 10 + u8(pos + 9) + 2 + ((u8(pos + 10) & 1u) != 0 ? 13 : 0);
      id = u8(pos + 15) | u8(pos + 16) << 8 | u8(pos + 17) << 16;
    } else if (start == 0xFE) {
      size = 6 + u8(pos + 9) + 2;
      id = u8(pos + 13);
    } else {
      break;
    }
    if (pos + 8 + size > b.size()) break;
    if (start == 0xFE) ++w.v1;
    ++w.by_id[id];
    ++w.total;
    w.frames.emplace_back(pos + 8, size);
    pos += 8 + size;
  }
  w.end = pos;
  return w;
}

void ExpectFirstTwoTlog(const TlogFile& f, const std::string& name, const double (&t_s)[2],
                        const double (&values)[2]) {
  const timeseries::TimedSignal s = Extract(f, name);
  ASSERT_GE(s.values.size(), 2u) << name;
  for (std::size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(s.t_s[i], t_s[i]) << name << " frame " << i;
    EXPECT_EQ(s.values[i], values[i]) << name << " frame " << i;
  }
}

TEST(TlogRealFile, ReadsEveryFrameOfTheArduSubLog) {
  const TlogFile f = Read(kArdusubTlogPath);
  const std::string bytes = TlogFileBytes(kArdusubTlogPath);
  const TlogHeaderWalk w = WalkTlogHeaders(bytes);
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.file_size, 1510263u);
  EXPECT_EQ(w.end, bytes.size());
  EXPECT_EQ(w.total, 35916u);
  EXPECT_EQ(f.records, 35916u);
  EXPECT_EQ(w.v1, 0u);  // all MAVLink 2
  EXPECT_EQ(f.v1_frames, 0u);
  EXPECT_EQ(f.signed_frames, 0u);
  EXPECT_EQ(f.bad_crc, 0u);  // every frame of a known message verified, ATTITUDE's with 39
  EXPECT_EQ(f.incompatible, 0u);
  EXPECT_EQ(f.bytes_skipped, 0u);
  EXPECT_TRUE(f.notes.empty());
  EXPECT_EQ(f.frame_counts, w.by_id);
  std::size_t known = 0;
  for (const MessageDef& m : KnownMessages()) {
    const auto it = w.by_id.find(m.id);
    EXPECT_EQ(f.FrameCount(m.name), it == w.by_id.end() ? 0u : it->second) << m.name;
    known += f.FrameCount(m.name);
  }
  EXPECT_EQ(known + f.unknown_frames, f.records);
  EXPECT_EQ(known, 13733u);
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 5245u);
  EXPECT_EQ(f.FrameCount("MANUAL_CONTROL"), 1450u);
  EXPECT_EQ(f.FrameCount("SERVO_OUTPUT_RAW"), 528u);
  EXPECT_EQ(f.FrameCount("COMMAND_LONG"), 9u);
  EXPECT_EQ(f.FrameCount("COMMAND_ACK"), 9u);  // the vehicle's answers to them
  EXPECT_EQ(f.first_time_us, 1683220541055000u);
  EXPECT_EQ(f.last_time_us, 1683220804485000u);

  // HEARTBEAT from four senders: the vehicle, two of its components, the ground station itself.
  EXPECT_EQ(f.Find("HEARTBEAT", 1, 1)->size(), 263u);
  EXPECT_EQ(f.Find("HEARTBEAT", 1, 100)->size(), 264u);
  EXPECT_EQ(f.Find("HEARTBEAT", 1, 194)->size(), 264u);
  EXPECT_EQ(f.Find("HEARTBEAT", 255, 190)->size(), 265u);
  EXPECT_EQ(f.FindMain("HEARTBEAT")->sysid, 255);
  // Sequence numbers, as a walk of the same bytes with Python counts them: the vehicle's own
  // stream is unbroken; the ground station's and two components' skip numbers (frames sent on
  // other links).
  const auto& senders = f.sequences.senders();
  EXPECT_EQ(senders.at(SenderKey(1, 1)).lost, 0u);
  EXPECT_EQ(senders.at(SenderKey(255, 190)).lost, 6388u);
  EXPECT_EQ(senders.at(SenderKey(1, 220)).lost, 263u);
  EXPECT_EQ(senders.at(SenderKey(1, 194)).lost, 1009u);
  EXPECT_EQ(f.sequences.lost(), 6388u + 263u + 1009u);
}

TEST(TlogRealFile, ValuesEqualAnIndependentDecoder) {
  const TlogFile f = Read(kArdusubTlogPath);
  ExpectFirstTwoTlog(f, "ATTITUDE.time_boot_ms", kAttitudeTimeS, kAttitudeTimeBootMs);
  ExpectFirstTwoTlog(f, "ATTITUDE.roll", kAttitudeTimeS, kAttitudeRoll);
  ExpectFirstTwoTlog(f, "ATTITUDE.pitch", kAttitudeTimeS, kAttitudePitch);
  ExpectFirstTwoTlog(f, "ATTITUDE.yaw", kAttitudeTimeS, kAttitudeYaw);
  ExpectFirstTwoTlog(f, "ATTITUDE.rollspeed", kAttitudeTimeS, kAttitudeRollspeed);
  ExpectFirstTwoTlog(f, "ATTITUDE.pitchspeed", kAttitudeTimeS, kAttitudePitchspeed);
  ExpectFirstTwoTlog(f, "ATTITUDE.yawspeed", kAttitudeTimeS, kAttitudeYawspeed);
  const std::pair<const char*, const double(*)[2]> servo[] = {
      {"time_usec", &kServoOutputRawTimeUsec},     {"servo1_raw", &kServoOutputRawServo1Raw},
      {"servo2_raw", &kServoOutputRawServo2Raw},   {"servo3_raw", &kServoOutputRawServo3Raw},
      {"servo4_raw", &kServoOutputRawServo4Raw},   {"servo5_raw", &kServoOutputRawServo5Raw},
      {"servo6_raw", &kServoOutputRawServo6Raw},   {"servo7_raw", &kServoOutputRawServo7Raw},
      {"servo8_raw", &kServoOutputRawServo8Raw},   {"port", &kServoOutputRawPort},
      {"servo9_raw", &kServoOutputRawServo9Raw},   {"servo10_raw", &kServoOutputRawServo10Raw},
      {"servo11_raw", &kServoOutputRawServo11Raw}, {"servo12_raw", &kServoOutputRawServo12Raw},
      {"servo13_raw", &kServoOutputRawServo13Raw}, {"servo14_raw", &kServoOutputRawServo14Raw},
      {"servo15_raw", &kServoOutputRawServo15Raw}, {"servo16_raw", &kServoOutputRawServo16Raw},
  };
  for (const auto& [field, values] : servo)
    ExpectFirstTwoTlog(f, std::string("SERVO_OUTPUT_RAW.") + field, kServoOutputRawTimeS, *values);
}

TEST(TlogRealFile, SignalsOfTheArduSubLog) {
  const TlogFile f = Read(kArdusubTlogPath);
  std::map<std::string, SignalInfo> signals;
  for (const SignalInfo& s : ListSignals(f)) signals.emplace(s.name, s);
  EXPECT_EQ(signals.at("ATTITUDE.pitchspeed").samples, 5245u);
  EXPECT_NEAR(signals.at("ATTITUDE.pitchspeed").median_rate_hz, 20.0, 0.01);
  EXPECT_EQ(signals.at("MANUAL_CONTROL.x").samples, 1450u);
  EXPECT_EQ(signals.at("MANUAL_CONTROL.x").sysid, 255);  // the ground station's joystick
  EXPECT_NEAR(signals.at("MANUAL_CONTROL.x").median_rate_hz, 23.81, 0.01);
  EXPECT_NEAR(signals.at("SERVO_OUTPUT_RAW.servo3_raw").median_rate_hz, 2.0, 0.01);
  EXPECT_NEAR(signals.at("RAW_IMU.xgyro").median_rate_hz, 2.0, 0.01);
  EXPECT_NEAR(signals.at("VFR_HUD.alt").median_rate_hz, 10.0, 0.01);
  EXPECT_EQ(signals.at("HEARTBEAT.base_mode").interpolation, timeseries::Interpolation::kHold);
  EXPECT_EQ(signals.at("HEARTBEAT.base_mode").sysid, 255);  // most frames: 265
  EXPECT_EQ(signals.at("HEARTBEAT@1:1.custom_mode").samples, 263u);
  for (const auto& [name, s] : signals) EXPECT_EQ(s.out_of_order, 0u) << name;
}

TEST(TlogRealFile, TheFrameDecoderReadsTheBareFramesAlike) {
  const std::string bytes = TlogFileBytes(kArdusubTlogPath);
  const TlogHeaderWalk w = WalkTlogHeaders(bytes);
  std::string frames;
  for (const auto& [offset, size] : w.frames) frames.append(bytes, offset, size);
  FrameDecoder decoder;
  std::map<std::uint32_t, std::size_t> by_id;
  std::vector<double> pitch;
  const FieldRef pitch_ref = *FindField(*FindByName("ATTITUDE"), "pitch");
  const FrameDecoder::FrameHandler on_frame = [&](const Frame& frame) {
    ++by_id[frame.msgid];
    if (frame.msgid == 30 && pitch.size() < 2) pitch.push_back(Field(frame, pitch_ref));
  };
  for (std::size_t at = 0; at < frames.size(); at += 4096)
    decoder.Feed(std::string_view(frames).substr(at, 4096), on_frame);
  decoder.Finish(on_frame);
  const DecoderCounters& c = decoder.counters();
  EXPECT_EQ(c.frames_ok, 13733u);
  EXPECT_EQ(c.unknown_message, 35916u - 13733u);
  EXPECT_EQ(c.bad_crc, 0u);
  EXPECT_EQ(c.bytes_skipped, 0u);
  EXPECT_EQ(c.cut, 0u);
  for (const auto& [id, n] : c.unknown_ids) by_id[id] += n;
  EXPECT_EQ(by_id, w.by_id);
  EXPECT_EQ(by_id.at(30), 5245u);
  EXPECT_EQ(decoder.sequences().lost(), 6388u + 263u + 1009u);
  ASSERT_EQ(pitch.size(), 2u);
  EXPECT_EQ(pitch[0], kAttitudePitch[0]);
  EXPECT_EQ(pitch[1], kAttitudePitch[1]);
}

// Cuts (every byte of the first 512, then every 97th of the first 64 KiB) and flipped bytes: a
// clean partial read that agrees with the independent walk of the same bytes, or a clear error,
// never a crash.
TEST(TlogRealFile, CutsAndFlippedBytesReadCleanly) {
  const std::string bytes = TlogFileBytes(kArdusubTlogPath).substr(0, 65536);
  for (std::size_t n = 9; n < bytes.size(); n += n < 512 ? 1 : 97) {
    SCOPED_TRACE(n);
    const std::string cut = bytes.substr(0, n);
    const TlogFile f = Parse(cut, "cut.tlog");
    const TlogHeaderWalk w = WalkTlogHeaders(cut);
    EXPECT_EQ(f.records, w.total);
    EXPECT_EQ(f.frame_counts, w.by_id);
    EXPECT_EQ(f.complete(), w.end == n);
    if (!f.complete()) {
      EXPECT_EQ(f.problem_offset, w.end);
      EXPECT_EQ(f.bytes_skipped, n - w.end);
    }
  }
  for (std::size_t k = 0; k < 200; ++k) {
    const std::size_t at = 9 + (k * 7919) % (bytes.size() - 9);
    SCOPED_TRACE(at);
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x5a);
    const TlogFile f = Parse(flipped, "flipped.tlog");
    EXPECT_LE(f.problem_offset, bytes.size());
    EXPECT_LE(f.bytes_skipped, bytes.size());
    EXPECT_LE(f.damage_count, 3u);  // one flipped byte breaks one record (or its neighbours)
    const std::vector<SignalInfo> signals = ListSignals(f);
    for (std::size_t i = 0; i < signals.size(); i += 1 + signals.size() / 4)
      EXPECT_EQ(Extract(f, signals[i].name).values.size(), signals[i].samples);
  }
  EXPECT_THROW(Read(std::string(ODONATA_MAVLINK_DIR) + "/ardusub_small.BIN"), TlogError);
}

#endif

}  // namespace
}  // namespace odonata::mavlink

#pragma once
// A small MAVLink encoder and telemetry-log writer for the tests, written apart from the code
// under test: payloads are laid out by hand at the offsets mavgen gives (the wire order written
// out below per message), the checksum is a bitwise CRC-16/MCRF4XX, and CRC_EXTRA comes from
// MAVLink's published tables (mavlink/c_library_v2 common.h MAVLINK_MESSAGE_CRCS), not from the
// table under test. The fuzz harness's seed files (tests/fuzz/corpus/mavlink_tlog) are logs of the
// same shape. The test files are compiled as one unity source: every helper lives here, once.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::mavlink::test_support {

/// 2023-05-04 17:15:41.055 UTC, µs: the real log's first record.
inline constexpr std::uint64_t kT0Us = 1'683'220'541'055'000;

/// CRC_EXTRA as MAVLink publishes it; 0 for an id not listed (an unknown message).
inline std::uint8_t PublishedCrcExtra(std::uint32_t id) {
  switch (id) {
    case 0:
      return 50;  // HEARTBEAT
    case 1:
      return 124;  // SYS_STATUS
    case 26:
      return 170;  // SCALED_IMU
    case 27:
      return 144;  // RAW_IMU
    case 30:
      return 39;  // ATTITUDE
    case 31:
      return 246;  // ATTITUDE_QUATERNION
    case 32:
      return 185;  // LOCAL_POSITION_NED
    case 36:
      return 222;  // SERVO_OUTPUT_RAW
    case 65:
      return 118;  // RC_CHANNELS
    case 69:
      return 243;  // MANUAL_CONTROL
    case 74:
      return 20;  // VFR_HUD
    case 76:
      return 152;  // COMMAND_LONG
    case 77:
      return 143;  // COMMAND_ACK
    case 83:
      return 22;  // ATTITUDE_TARGET
    case 105:
      return 93;  // HIGHRES_IMU
    case 375:
      return 251;  // ACTUATOR_OUTPUT_STATUS
    default:
      return 0;
  }
}

/// CRC-16/MCRF4XX bit by bit (reflected polynomial 0x8408, initial 0xFFFF, no final XOR).
inline std::uint16_t BitwiseCrc(std::string_view bytes, std::uint16_t crc = 0xFFFF) {
  for (const char c : bytes) {
    crc = static_cast<std::uint16_t>(crc ^ static_cast<std::uint8_t>(c));
    for (int bit = 0; bit < 8; ++bit)
      crc = static_cast<std::uint16_t>((crc & 1) != 0 ? (crc >> 1) ^ 0x8408 : crc >> 1);
  }
  return crc;
}

/// Little-endian payload bytes, appended field by field in wire order.
class PayloadBytes {
 public:
  PayloadBytes& U8(unsigned v) { return Int(v, 1); }
  PayloadBytes& U16(unsigned v) { return Int(v, 2); }
  PayloadBytes& U32(std::uint32_t v) { return Int(v, 4); }
  PayloadBytes& U64(std::uint64_t v) { return Int(v, 8); }
  PayloadBytes& F32(float v) {
    std::uint32_t bits = 0;
    std::memcpy(&bits, &v, sizeof bits);
    return Int(bits, 4);
  }
  const std::string& str() const { return bytes_; }

 private:
  PayloadBytes& Int(std::uint64_t v, int n) {
    for (int i = 0; i < n; ++i) bytes_ += static_cast<char>((v >> (8 * i)) & 0xFF);
    return *this;
  }
  std::string bytes_;
};

/// ATTITUDE (30): wire order time_boot_ms, roll, pitch, yaw, rollspeed, pitchspeed, yawspeed.
inline std::string AttitudePayload(std::uint32_t time_boot_ms, float roll, float pitch, float yaw,
                                   float rollspeed, float pitchspeed, float yawspeed) {
  return PayloadBytes()
      .U32(time_boot_ms)
      .F32(roll)
      .F32(pitch)
      .F32(yaw)
      .F32(rollspeed)
      .F32(pitchspeed)
      .F32(yawspeed)
      .str();
}

/// SERVO_OUTPUT_RAW (36): time_usec (uint32), servo1..8_raw, port, then the extensions
/// servo9..16_raw; `servos` gives servo1.. in order (8 of them: no extensions; 16: all).
inline std::string ServoPayload(std::uint32_t time_usec, unsigned port,
                                const std::vector<unsigned>& servos) {
  PayloadBytes p;
  p.U32(time_usec);
  for (std::size_t i = 0; i < 8; ++i) p.U16(i < servos.size() ? servos[i] : 0u);
  p.U8(port);
  for (std::size_t i = 8; i < servos.size(); ++i) p.U16(servos[i]);
  return p.str();
}

/// HEARTBEAT (0): custom_mode (uint32), type, autopilot, base_mode, system_status,
/// mavlink_version.
inline std::string HeartbeatPayload(std::uint32_t custom_mode, unsigned type, unsigned base_mode) {
  return PayloadBytes().U32(custom_mode).U8(type).U8(3).U8(base_mode).U8(4).U8(3).str();
}

/// ACTUATOR_OUTPUT_STATUS (375): time_usec (uint64), active (uint32), actuator (float[32]).
inline std::string ActuatorPayload(std::uint64_t time_usec, const std::vector<float>& actuator) {
  PayloadBytes p;
  p.U64(time_usec).U32(static_cast<std::uint32_t>(actuator.size()));
  for (std::size_t i = 0; i < 32; ++i) p.F32(i < actuator.size() ? actuator[i] : 0.0f);
  return p.str();
}

/// What to encode: a frame of message `msgid` with `payload` (its full length).
struct FrameSpec {
  int version = 2;  ///< 1 or 2
  std::uint32_t msgid = 30;
  std::string payload;
  std::uint8_t seq = 0;
  std::uint8_t sysid = 1;
  std::uint8_t compid = 1;
  std::uint8_t incompat = 0;  ///< bit 0: a 13-byte signature follows the checksum
  std::uint8_t compat = 0;
  bool truncate = true;  ///< MAVLink 2: cut the payload's trailing zeros (one byte stays)
  std::string signature = std::string(13, '\x5a');  ///< link id, timestamp, signature
};

/// The frame's bytes, as a MAVLink 1 or 2 sender writes them.
inline std::string EncodeFrame(const FrameSpec& f) {
  std::string payload = f.payload;
  if (f.version == 2 && f.truncate)
    while (payload.size() > 1 && payload.back() == '\0') payload.pop_back();
  std::string frame;
  if (f.version == 1) {
    frame = {'\xFE',
             static_cast<char>(payload.size()),
             static_cast<char>(f.seq),
             static_cast<char>(f.sysid),
             static_cast<char>(f.compid),
             static_cast<char>(f.msgid)};
  } else {
    frame = {'\xFD',
             static_cast<char>(payload.size()),
             static_cast<char>(f.incompat),
             static_cast<char>(f.compat),
             static_cast<char>(f.seq),
             static_cast<char>(f.sysid),
             static_cast<char>(f.compid),
             static_cast<char>(f.msgid & 0xFF),
             static_cast<char>((f.msgid >> 8) & 0xFF),
             static_cast<char>((f.msgid >> 16) & 0xFF)};
  }
  frame += payload;
  std::uint16_t crc = BitwiseCrc(std::string_view(frame).substr(1));
  crc = BitwiseCrc(std::string(1, static_cast<char>(PublishedCrcExtra(f.msgid))), crc);
  frame += static_cast<char>(crc & 0xFF);
  frame += static_cast<char>(crc >> 8);
  if (f.version == 2 && (f.incompat & 1u) != 0) frame += f.signature;
  return frame;
}

/// A frame of ATTITUDE with these values, MAVLink 2, from sysid:compid.
inline std::string AttitudeFrame(std::uint8_t seq, std::uint32_t time_boot_ms, float pitch,
                                 float pitchspeed, std::uint8_t sysid = 1,
                                 std::uint8_t compid = 1) {
  FrameSpec f;
  f.msgid = 30;
  f.payload = AttitudePayload(time_boot_ms, 0.25f, pitch, -1.5f, 0.125f, pitchspeed, 0.0f);
  f.seq = seq;
  f.sysid = sysid;
  f.compid = compid;
  return EncodeFrame(f);
}

/// A frame of a message the table does not know (AHRS2, id 178), MAVLink 2.
inline std::string UnknownFrame(std::uint8_t seq, std::uint8_t sysid = 1, std::uint8_t compid = 1) {
  FrameSpec f;
  f.msgid = 178;
  f.payload = PayloadBytes().F32(0.5f).F32(-0.5f).F32(2.0f).U32(7).U32(9).U32(11).str();
  f.seq = seq;
  f.sysid = sysid;
  f.compid = compid;
  return EncodeFrame(f);
}

/// A telemetry log written record by record: an 8-byte big-endian timestamp, then a frame.
class TlogWriter {
 public:
  /// Writes a record; returns its offset.
  std::size_t Record(std::uint64_t t_us, const std::string& frame) {
    const std::size_t offset = bytes_.size();
    for (int i = 7; i >= 0; --i) bytes_ += static_cast<char>((t_us >> (8 * i)) & 0xFF);
    bytes_ += frame;
    starts_.push_back(offset);
    return offset;
  }
  /// Writes `raw` as it is (garbage); returns its offset.
  std::size_t Raw(const std::string& raw) {
    const std::size_t offset = bytes_.size();
    bytes_ += raw;
    return offset;
  }
  const std::string& bytes() const { return bytes_; }
  std::size_t size() const { return bytes_.size(); }
  /// Where each record starts, in order.
  const std::vector<std::size_t>& record_starts() const { return starts_; }

 private:
  std::string bytes_;
  std::vector<std::size_t> starts_;
};

/// A small flight: ATTITUDE at 10 Hz (1:1), SERVO_OUTPUT_RAW with extensions at 5 Hz (1:1),
/// HEARTBEAT from the vehicle (1:1, 3 frames) and the ground station (255:190, 2 frames), an
/// unknown message (AHRS2, 2 frames), one MAVLink 1 frame and one signed frame: 15 records in
/// 0.403 s, every sender's sequence unbroken.
inline TlogWriter SmallFlightTlog() {
  TlogWriter w;
  std::uint8_t seq = 0;
  std::uint8_t gcs_seq = 0;
  for (int i = 0; i < 5; ++i) {
    const std::uint64_t t_us = kT0Us + static_cast<std::uint64_t>(i) * 100'000;
    w.Record(t_us, AttitudeFrame(seq++, 1000u + 100u * static_cast<std::uint32_t>(i),
                                 0.01f * static_cast<float>(i), -0.5f + static_cast<float>(i)));
    if (i % 2 == 0) {
      FrameSpec servo;
      servo.msgid = 36;
      servo.seq = seq++;
      servo.version = i == 4 ? 1 : 2;  // the last one MAVLink 1: base fields only
      const unsigned pwm = 1500u + 10u * static_cast<unsigned>(i);
      servo.payload =
          ServoPayload(static_cast<std::uint32_t>(t_us % 1'000'000'000), 0,
                       servo.version == 1
                           ? std::vector<unsigned>{pwm, 1500, pwm + 1, 1500, 1500, 1500, 1500, 1500}
                           : std::vector<unsigned>{pwm, 1500, pwm + 1, 1500, 1500, 1500, 1500, 1500,
                                                   0, 0, 0, 1100, 1100, 0, 0, 0});
      w.Record(t_us + 2'000, EncodeFrame(servo));
      FrameSpec heartbeat;
      heartbeat.msgid = 0;
      heartbeat.seq = seq++;
      heartbeat.payload = HeartbeatPayload(19, 12, i == 0 ? 81 : 209);
      heartbeat.incompat = i == 2 ? 1 : 0;  // the second one signed
      w.Record(t_us + 3'000, EncodeFrame(heartbeat));
    }
    if (i == 1 || i == 3) {
      w.Record(t_us + 4'000, UnknownFrame(seq++));
      FrameSpec gcs;
      gcs.msgid = 0;
      gcs.seq = gcs_seq++;
      gcs.sysid = 255;
      gcs.compid = 190;
      gcs.payload = HeartbeatPayload(0, 6, 0);
      w.Record(t_us + 5'000, EncodeFrame(gcs));
    }
  }
  return w;
}

}  // namespace odonata::mavlink::test_support

#pragma once
// MAVLink 2 frames written: the few odonata sends (odonata-mavlink's --request-rate), from the one
// field table (mavlink_messages.hpp), so that what is written is what the decoder reads.
//
// A frame: 0xFD, payload length, incompat flags (0: unsigned), compat flags (0), seq, sysid,
// compid, the message id (3 bytes, little-endian), the payload with its trailing zero bytes cut
// (one byte stays, as MAVLink 2 senders do), the checksum over the frame after its start byte and
// the message's CRC_EXTRA (mavlink_crc.hpp). odonata sends as a ground station does: sysid 255,
// compid 190 (MAV_COMP_ID_MISSIONPLANNER), so a vehicle's reply goes to every ground station.

#include <cstdint>
#include <string>
#include <string_view>

#include "mavlink/mavlink_messages.hpp"

namespace odonata::mavlink {

inline constexpr std::uint8_t kGroundStationSysid = 255;
inline constexpr std::uint8_t kGroundStationCompid = 190;
/// MAV_CMD_SET_MESSAGE_INTERVAL: param1 the message id, param2 the interval in microseconds.
inline constexpr std::uint16_t kCmdSetMessageInterval = 511;

/// A payload of one message, its fields set by name; fields not set are zero.
class PayloadBuilder {
 public:
  explicit PayloadBuilder(const MessageDef& message);
  /// Sets `field` ("command", "param2", "actuator[3]") to `value`, converted to the field's type
  /// (an integer field takes the value rounded toward zero).
  /// @throws std::invalid_argument for a field the message does not have.
  PayloadBuilder& Set(std::string_view field, double value);
  /// All of the message's payload bytes (MessageDef::length).
  const std::string& bytes() const { return bytes_; }

 private:
  const MessageDef& message_;
  std::string bytes_;
};

/// The MAVLink 2 frame of `message` with `payload` (its full length), unsigned.
std::string EncodeFrameV2(const MessageDef& message, std::string_view payload, std::uint8_t seq,
                          std::uint8_t sysid = kGroundStationSysid,
                          std::uint8_t compid = kGroundStationCompid);

/// COMMAND_LONG asking `target_system`:`target_component` to send message `message_id` every
/// `interval_us` microseconds (MAV_CMD_SET_MESSAGE_INTERVAL; -1 stops it, 0 restores its default).
std::string SetMessageIntervalPayload(std::uint8_t target_system, std::uint8_t target_component,
                                      std::uint32_t message_id, double interval_us);

}  // namespace odonata::mavlink

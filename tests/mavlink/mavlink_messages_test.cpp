// The table of MAVLink messages: CRC_EXTRA computed as mavgen does equals MAVLink's published
// values, the wire layout (fields by type size, stable, extensions after) equals mavgen's offsets
// and lengths, and fields are found by name and element.
#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include "mavlink/mavlink_crc.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink_test_support.hpp"

namespace odonata::mavlink {
namespace {

struct PublishedMessage {
  const char* name;
  std::uint32_t id;
  std::uint8_t crc_extra;
  std::size_t min_length;  // mavgen's: the base fields
  std::size_t max_length;  // mavgen's: with the extensions
};

// MAVLINK_MESSAGE_CRCS of mavlink/c_library_v2 common.h ({id, crc_extra, min, max, …}), checked
// against pymavlink's message_checksum run on common.xml and minimal.xml: the same numbers.
const PublishedMessage kPublished[] = {
    {"HEARTBEAT", 0, 50, 9, 9},
    {"SYS_STATUS", 1, 124, 31, 43},
    {"SCALED_IMU", 26, 170, 22, 24},
    {"RAW_IMU", 27, 144, 26, 29},
    {"ATTITUDE", 30, 39, 28, 28},
    {"ATTITUDE_QUATERNION", 31, 246, 32, 48},
    {"LOCAL_POSITION_NED", 32, 185, 28, 28},
    {"SERVO_OUTPUT_RAW", 36, 222, 21, 37},
    {"RC_CHANNELS", 65, 118, 42, 42},
    {"MANUAL_CONTROL", 69, 243, 11, 30},
    {"VFR_HUD", 74, 20, 20, 20},
    {"COMMAND_LONG", 76, 152, 33, 33},
    {"COMMAND_ACK", 77, 143, 3, 10},
    {"ATTITUDE_TARGET", 83, 22, 37, 37},
    {"HIGHRES_IMU", 105, 93, 62, 63},
    {"ACTUATOR_OUTPUT_STATUS", 375, 251, 140, 140},
};

// The offset of `field` in `message`, or -1.
long OffsetOf(const std::string& message, const std::string& field) {
  const MessageDef* m = FindByName(message);
  if (m == nullptr) return -1;
  const std::optional<FieldRef> f = FindField(*m, field);
  return f ? static_cast<long>(f->offset) : -1;
}

TEST(MavlinkMessages, CrcExtraEqualsThePublishedValues) {
  EXPECT_EQ(KnownMessages().size(), std::size(kPublished));
  for (const PublishedMessage& p : kPublished) {
    SCOPED_TRACE(p.name);
    const MessageDef* m = FindByName(p.name);
    ASSERT_NE(m, nullptr);
    EXPECT_EQ(m->id, p.id);
    EXPECT_EQ(FindById(p.id), m);
    EXPECT_EQ(static_cast<int>(CrcExtra(*m)), static_cast<int>(p.crc_extra));
    EXPECT_EQ(static_cast<int>(m->crc_extra), static_cast<int>(p.crc_extra));
    EXPECT_EQ(static_cast<int>(test_support::PublishedCrcExtra(p.id)),
              static_cast<int>(p.crc_extra));
    EXPECT_EQ(m->base_length, p.min_length);
    EXPECT_EQ(m->length, p.max_length);
  }
}

TEST(MavlinkMessages, CrcExtraLeavesExtensionsOutAndFollowsTheFields) {
  MessageDef m = *FindByName("SERVO_OUTPUT_RAW");
  const std::uint8_t published = CrcExtra(m);
  m.fields.push_back(FieldDef{FieldType::kUint16, "servo17_raw", 0, true});
  EXPECT_EQ(CrcExtra(m), published);  // an extension added: the same CRC_EXTRA
  m.fields.back().extension = false;
  EXPECT_NE(CrcExtra(m), published);
  MessageDef renamed = *FindByName("ATTITUDE");
  renamed.fields[1].name = "rol";
  EXPECT_NE(CrcExtra(renamed), 39);
  MessageDef longer = *FindByName("ATTITUDE_TARGET");
  longer.fields[2].array_length = 5;  // q: float[5]
  EXPECT_NE(CrcExtra(longer), 22);
}

TEST(MavlinkMessages, TheChecksumIsCrc16Mcrf4xx) {
  // The check value of CRC-16/MCRF4XX over "123456789".
  EXPECT_EQ(CrcAccumulate(std::string_view("123456789"), kCrcInit), 0x6F91);
  EXPECT_EQ(test_support::BitwiseCrc("123456789"), 0x6F91);
  const char raw[] = "\xFD\x1C\x00\x00\x07\x01\x01\x1E\x00\x00 any bytes \xFF\xFE";
  const std::string bytes(raw, sizeof raw - 1);  // NULs included
  EXPECT_EQ(CrcAccumulate(bytes, kCrcInit), test_support::BitwiseCrc(bytes));
}

TEST(MavlinkMessages, WireLayoutSortsBaseFieldsBySizeAndPutsExtensionsAfter) {
  // ATTITUDE: all 4-byte fields, in XML order.
  EXPECT_EQ(OffsetOf("ATTITUDE", "time_boot_ms"), 0);
  EXPECT_EQ(OffsetOf("ATTITUDE", "roll"), 4);
  EXPECT_EQ(OffsetOf("ATTITUDE", "pitchspeed"), 20);
  EXPECT_EQ(OffsetOf("ATTITUDE", "yawspeed"), 24);
  // SERVO_OUTPUT_RAW: time_usec, servo1..8 (uint16), port (uint8), then the extensions.
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "time_usec"), 0);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "servo1_raw"), 4);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "servo3_raw"), 8);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "servo8_raw"), 18);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "port"), 20);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "servo9_raw"), 21);
  EXPECT_EQ(OffsetOf("SERVO_OUTPUT_RAW", "servo16_raw"), 35);
  // HEARTBEAT: custom_mode (uint32) first, then the uint8s in XML order.
  EXPECT_EQ(OffsetOf("HEARTBEAT", "custom_mode"), 0);
  EXPECT_EQ(OffsetOf("HEARTBEAT", "type"), 4);
  EXPECT_EQ(OffsetOf("HEARTBEAT", "base_mode"), 6);
  EXPECT_EQ(OffsetOf("HEARTBEAT", "mavlink_version"), 8);
  // ATTITUDE_TARGET: an array sorts by its element's size.
  EXPECT_EQ(OffsetOf("ATTITUDE_TARGET", "q[0]"), 4);
  EXPECT_EQ(OffsetOf("ATTITUDE_TARGET", "q[3]"), 16);
  EXPECT_EQ(OffsetOf("ATTITUDE_TARGET", "body_roll_rate"), 20);
  EXPECT_EQ(OffsetOf("ATTITUDE_TARGET", "thrust"), 32);
  EXPECT_EQ(OffsetOf("ATTITUDE_TARGET", "type_mask"), 36);
  // MANUAL_CONTROL: int16s and buttons, target, then the extensions in XML order, unsorted.
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "x"), 0);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "buttons"), 8);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "target"), 10);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "buttons2"), 11);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "enabled_extensions"), 13);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "s"), 14);
  EXPECT_EQ(OffsetOf("MANUAL_CONTROL", "aux6"), 28);
  // RAW_IMU: the extensions id (uint8) then temperature (int16), unaligned.
  EXPECT_EQ(OffsetOf("RAW_IMU", "zmag"), 24);
  EXPECT_EQ(OffsetOf("RAW_IMU", "id"), 26);
  EXPECT_EQ(OffsetOf("RAW_IMU", "temperature"), 27);
  // HIGHRES_IMU, COMMAND_LONG, ACTUATOR_OUTPUT_STATUS.
  EXPECT_EQ(OffsetOf("HIGHRES_IMU", "xgyro"), 20);
  EXPECT_EQ(OffsetOf("HIGHRES_IMU", "fields_updated"), 60);
  EXPECT_EQ(OffsetOf("HIGHRES_IMU", "id"), 62);
  EXPECT_EQ(OffsetOf("COMMAND_LONG", "param7"), 24);
  EXPECT_EQ(OffsetOf("COMMAND_LONG", "command"), 28);
  EXPECT_EQ(OffsetOf("COMMAND_LONG", "target_system"), 30);
  EXPECT_EQ(OffsetOf("COMMAND_LONG", "confirmation"), 32);
  EXPECT_EQ(OffsetOf("ACTUATOR_OUTPUT_STATUS", "active"), 8);
  EXPECT_EQ(OffsetOf("ACTUATOR_OUTPUT_STATUS", "actuator[0]"), 12);
  EXPECT_EQ(OffsetOf("ACTUATOR_OUTPUT_STATUS", "actuator[31]"), 136);

  // The layout covers the payload without gaps or overlaps.
  for (const MessageDef& m : KnownMessages()) {
    SCOPED_TRACE(m.name);
    const std::vector<WireField> wire = WireLayout(m);
    ASSERT_EQ(wire.size(), m.fields.size());
    std::size_t at = 0;
    for (const WireField& w : wire) {
      EXPECT_EQ(w.offset, at) << w.field.name;
      at += w.field.size();
    }
    EXPECT_EQ(at, m.length);
  }
}

TEST(MavlinkMessages, FieldsAreFoundByNameAndElement) {
  const MessageDef& actuators = *FindByName("ACTUATOR_OUTPUT_STATUS");
  const std::optional<FieldRef> a1 = FindField(actuators, "actuator[1]");
  ASSERT_TRUE(a1.has_value());
  EXPECT_EQ(a1->offset, 16u);
  EXPECT_EQ(a1->type, FieldType::kFloat);
  EXPECT_FALSE(FindField(actuators, "actuator").has_value());      // an array needs its index
  EXPECT_FALSE(FindField(actuators, "actuator[32]").has_value());  // past the end
  EXPECT_FALSE(FindField(actuators, "actuator[]").has_value());
  EXPECT_FALSE(FindField(actuators, "actuator[x]").has_value());
  EXPECT_FALSE(FindField(actuators, "active[0]").has_value());  // no array
  EXPECT_FALSE(FindField(actuators, "nope").has_value());
  const std::optional<FieldRef> mode = FindField(*FindByName("HEARTBEAT"), "custom_mode");
  ASSERT_TRUE(mode.has_value());
  EXPECT_EQ(mode->type, FieldType::kUint32);

  EXPECT_EQ(FindByName("AHRS2"), nullptr);
  EXPECT_EQ(FindByName("attitude"), nullptr);  // names are upper case, as MAVLink writes them
  EXPECT_EQ(FindById(178), nullptr);
  EXPECT_EQ(FindById(0xFFFFFF), nullptr);
  EXPECT_STREQ(TypeName(FieldType::kUint8), "uint8_t");
  EXPECT_STREQ(TypeName(FieldType::kFloat), "float");
  EXPECT_EQ(SizeOf(FieldType::kDouble), 8u);
}

TEST(MavlinkMessages, ValuesReadLittleEndianWithTheirSign) {
  const std::uint8_t minus_two[] = {0xFE, 0xFF};
  EXPECT_EQ(ReadValue(minus_two, FieldType::kInt16), -2.0);
  EXPECT_EQ(ReadValue(minus_two, FieldType::kUint16), 65534.0);
  const std::uint8_t min_i8[] = {0x80};
  EXPECT_EQ(ReadValue(min_i8, FieldType::kInt8), -128.0);
  EXPECT_EQ(ReadValue(min_i8, FieldType::kUint8), 128.0);
  const std::uint8_t big[] = {0x01, 0x02, 0x03, 0x04, 0x05, 0x06, 0x07, 0x08};
  EXPECT_EQ(ReadValue(big, FieldType::kUint32), 67305985.0);
  EXPECT_EQ(ReadValue(big, FieldType::kUint64), 578437695752307201.0);
  const std::uint8_t all_ones[] = {0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF};
  EXPECT_EQ(ReadValue(all_ones, FieldType::kInt64), -1.0);
  EXPECT_EQ(ReadValue(all_ones, FieldType::kInt32), -1.0);
  const std::string f = test_support::PayloadBytes().F32(-1.5f).str();
  EXPECT_EQ(ReadValue(reinterpret_cast<const std::uint8_t*>(f.data()), FieldType::kFloat), -1.5);
  const double d = 0.1;
  std::uint8_t d_bytes[8];
  std::memcpy(d_bytes, &d, sizeof d);  // the host is little-endian (x86-64, ARM)
  EXPECT_EQ(ReadValue(d_bytes, FieldType::kDouble), 0.1);
}

}  // namespace
}  // namespace odonata::mavlink

#pragma once
// The MAVLink messages odonata reads: one table of their fields as MAVLink's XML definitions give
// them (mavlink/mavlink, message_definitions/v1.0/minimal.xml and common.xml), and what mavgen
// derives from it, so that nothing is copied from generated code.
//
// Wire layout (MAVLink 1 and 2 alike): the base fields sorted by the size of their type, largest
// first, stable (fields of one size keep their XML order; an array sorts by its element's size),
// then the extension fields (those after <extensions/>) in XML order. Little-endian, packed. A
// MAVLink 1 payload holds the base fields only; MAVLink 2 may add the extensions and cuts the
// payload's trailing zero bytes, which a reader puts back.
//
// CRC_EXTRA (pymavlink generator/mavparse.py, message_checksum): CRC-16/MCRF4XX over "NAME " and,
// for each base field in wire order, "type " and "name " and, for an array, its length as one
// byte; the byte is (crc & 0xFF) ^ (crc >> 8). Extensions are left out, so that adding one keeps
// a message's CRC_EXTRA. HEARTBEAT's mavlink_version (XML type uint8_t_mavlink_version) counts as
// uint8_t, as mavgen reads it.

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::mavlink {

/// The C types of MAVLink fields.
enum class FieldType : std::uint8_t {
  kChar,
  kInt8,
  kUint8,
  kInt16,
  kUint16,
  kInt32,
  kUint32,
  kInt64,
  kUint64,
  kFloat,
  kDouble,
};

/// Bytes one value of `type` takes on the wire.
std::size_t SizeOf(FieldType type);
/// The C type's name as the XML writes it ("uint8_t", "float"): what CRC_EXTRA covers.
const char* TypeName(FieldType type);

/// One field of a message, as its XML definition gives it.
struct FieldDef {
  FieldType type = FieldType::kUint8;
  std::string name;
  std::uint8_t array_length = 0;  ///< 0: one value; n: an array of n (float[4] q)
  bool extension = false;         ///< listed after <extensions/>: after the base fields on the wire

  std::size_t count() const { return array_length == 0 ? 1 : array_length; }
  /// Bytes of the whole field on the wire.
  std::size_t size() const { return SizeOf(type) * count(); }
};

/// A field at its place on the wire.
struct WireField {
  FieldDef field;
  std::size_t offset = 0;  ///< of its first byte, from the start of the payload
};

/// One message of the table. `id`, `name` and `fields` are the table's; the rest is derived from
/// them when the table is built.
struct MessageDef {
  std::uint32_t id = 0;
  std::string name;              ///< "ATTITUDE"
  std::vector<FieldDef> fields;  ///< in XML order: the base fields, then the extensions

  std::vector<WireField> wire;  ///< WireLayout(*this)
  std::size_t base_length = 0;  ///< payload bytes of the base fields (mavgen's minimum length)
  std::size_t length = 0;       ///< payload bytes of all fields (mavgen's maximum length)
  std::uint8_t crc_extra = 0;   ///< CrcExtra(*this)
};

/// The fields of `message` in wire order, each with its offset (see above).
std::vector<WireField> WireLayout(const MessageDef& message);

/// mavgen's CRC_EXTRA of `message`, computed from its name and base fields (see above).
std::uint8_t CrcExtra(const MessageDef& message);

/// Every message the table holds, by id: HEARTBEAT (0), SYS_STATUS (1), SCALED_IMU (26),
/// RAW_IMU (27), ATTITUDE (30), ATTITUDE_QUATERNION (31), LOCAL_POSITION_NED (32),
/// SERVO_OUTPUT_RAW (36), RC_CHANNELS (65), MANUAL_CONTROL (69), VFR_HUD (74), COMMAND_LONG (76),
/// COMMAND_ACK (77), ATTITUDE_TARGET (83), HIGHRES_IMU (105), ACTUATOR_OUTPUT_STATUS (375). Built
/// once, on first use; the references and pointers into it stay valid for the program's life.
const std::vector<MessageDef>& KnownMessages();

/// The message with id `id`, or nullptr when the table does not hold it.
const MessageDef* FindById(std::uint32_t id);
/// The message called `name` ("ATTITUDE"), or nullptr.
const MessageDef* FindByName(std::string_view name);

/// Where one value of a message lies in its (zero-extended) payload.
struct FieldRef {
  FieldType type = FieldType::kUint8;
  std::size_t offset = 0;  ///< of the value's first byte, from the start of the payload
};

/// The value `name` of `message`: a field ("pitchspeed") or an element of an array field
/// ("actuator[1]", "q[0]"); nullopt for a name that is neither, an array without an index, an
/// index past the array's end, or a char field (text, no number).
std::optional<FieldRef> FindField(const MessageDef& message, std::string_view name);

/// The value of `type` at `p`, little-endian, independent of the host (64-bit integers above 2^53
/// rounded to the nearest double).
double ReadValue(const std::uint8_t* p, FieldType type);

/// The value `field` refers to in `payload`.
/// @pre payload holds field.offset + SizeOf(field.type) bytes (a zero-extended payload of the
///   message `field` was found in does).
inline double FieldValue(const std::uint8_t* payload, const FieldRef& field) {
  return ReadValue(payload + field.offset, field.type);
}

}  // namespace odonata::mavlink

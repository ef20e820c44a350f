#include "mavlink/mavlink_messages.hpp"

#include <algorithm>
#include <cstring>
#include <utility>

#include "mavlink/mavlink_crc.hpp"

namespace odonata::mavlink {
namespace {

// A base field of the table; an extension field.
FieldDef TableField(FieldType type, const char* name, std::uint8_t array_length = 0) {
  return FieldDef{type, name, array_length, false};
}
FieldDef TableExtension(FieldType type, const char* name, std::uint8_t array_length = 0) {
  return FieldDef{type, name, array_length, true};
}

// "servo1_raw" … "servoN_raw" from `first` on, as base fields or extensions.
void NumberedFields(std::vector<FieldDef>& out, FieldType type, const char* stem, int first,
                    int last, const char* suffix, bool extension) {
  for (int i = first; i <= last; ++i)
    out.push_back(FieldDef{type, stem + std::to_string(i) + suffix, 0, extension});
}

MessageDef TableMessage(std::uint32_t id, const char* name, std::vector<FieldDef> fields) {
  MessageDef m;
  m.id = id;
  m.name = name;
  m.fields = std::move(fields);
  return m;
}

// The table, transcribed from minimal.xml (HEARTBEAT) and common.xml (mavlink/mavlink master,
// July 2026): each message's fields in XML order, the extensions after the marker.
std::vector<MessageDef> TableRows() {
  constexpr FieldType kI8 = FieldType::kInt8, kU8 = FieldType::kUint8, kI16 = FieldType::kInt16,
                      kU16 = FieldType::kUint16, kI32 = FieldType::kInt32,
                      kU32 = FieldType::kUint32, kU64 = FieldType::kUint64, kF = FieldType::kFloat;
  std::vector<MessageDef> t;
  t.push_back(TableMessage(0, "HEARTBEAT",
                           {TableField(kU8, "type"), TableField(kU8, "autopilot"),
                            TableField(kU8, "base_mode"), TableField(kU32, "custom_mode"),
                            TableField(kU8, "system_status"), TableField(kU8, "mavlink_version")}));
  t.push_back(
      TableMessage(1, "SYS_STATUS",
                   {TableField(kU32, "onboard_control_sensors_present"),
                    TableField(kU32, "onboard_control_sensors_enabled"),
                    TableField(kU32, "onboard_control_sensors_health"), TableField(kU16, "load"),
                    TableField(kU16, "voltage_battery"), TableField(kI16, "current_battery"),
                    TableField(kI8, "battery_remaining"), TableField(kU16, "drop_rate_comm"),
                    TableField(kU16, "errors_comm"), TableField(kU16, "errors_count1"),
                    TableField(kU16, "errors_count2"), TableField(kU16, "errors_count3"),
                    TableField(kU16, "errors_count4"),
                    TableExtension(kU32, "onboard_control_sensors_present_extended"),
                    TableExtension(kU32, "onboard_control_sensors_enabled_extended"),
                    TableExtension(kU32, "onboard_control_sensors_health_extended")}));
  const std::vector<FieldDef> imu9 = {
      TableField(kI16, "xacc"),  TableField(kI16, "yacc"),  TableField(kI16, "zacc"),
      TableField(kI16, "xgyro"), TableField(kI16, "ygyro"), TableField(kI16, "zgyro"),
      TableField(kI16, "xmag"),  TableField(kI16, "ymag"),  TableField(kI16, "zmag")};
  std::vector<FieldDef> scaled_imu = {TableField(kU32, "time_boot_ms")};
  scaled_imu.insert(scaled_imu.end(), imu9.begin(), imu9.end());
  scaled_imu.push_back(TableExtension(kI16, "temperature"));
  t.push_back(TableMessage(26, "SCALED_IMU", std::move(scaled_imu)));
  std::vector<FieldDef> raw_imu = {TableField(kU64, "time_usec")};
  raw_imu.insert(raw_imu.end(), imu9.begin(), imu9.end());
  raw_imu.push_back(TableExtension(kU8, "id"));
  raw_imu.push_back(TableExtension(kI16, "temperature"));
  t.push_back(TableMessage(27, "RAW_IMU", std::move(raw_imu)));
  t.push_back(
      TableMessage(30, "ATTITUDE",
                   {TableField(kU32, "time_boot_ms"), TableField(kF, "roll"),
                    TableField(kF, "pitch"), TableField(kF, "yaw"), TableField(kF, "rollspeed"),
                    TableField(kF, "pitchspeed"), TableField(kF, "yawspeed")}));
  t.push_back(TableMessage(31, "ATTITUDE_QUATERNION",
                           {TableField(kU32, "time_boot_ms"), TableField(kF, "q1"),
                            TableField(kF, "q2"), TableField(kF, "q3"), TableField(kF, "q4"),
                            TableField(kF, "rollspeed"), TableField(kF, "pitchspeed"),
                            TableField(kF, "yawspeed"), TableExtension(kF, "repr_offset_q", 4)}));
  t.push_back(TableMessage(
      32, "LOCAL_POSITION_NED",
      {TableField(kU32, "time_boot_ms"), TableField(kF, "x"), TableField(kF, "y"),
       TableField(kF, "z"), TableField(kF, "vx"), TableField(kF, "vy"), TableField(kF, "vz")}));
  std::vector<FieldDef> servo = {TableField(kU32, "time_usec"), TableField(kU8, "port")};
  NumberedFields(servo, kU16, "servo", 1, 8, "_raw", false);
  NumberedFields(servo, kU16, "servo", 9, 16, "_raw", true);
  t.push_back(TableMessage(36, "SERVO_OUTPUT_RAW", std::move(servo)));
  std::vector<FieldDef> rc = {TableField(kU32, "time_boot_ms"), TableField(kU8, "chancount")};
  NumberedFields(rc, kU16, "chan", 1, 18, "_raw", false);
  rc.push_back(TableField(kU8, "rssi"));
  t.push_back(TableMessage(65, "RC_CHANNELS", std::move(rc)));
  std::vector<FieldDef> manual = {TableField(kU8, "target"),
                                  TableField(kI16, "x"),
                                  TableField(kI16, "y"),
                                  TableField(kI16, "z"),
                                  TableField(kI16, "r"),
                                  TableField(kU16, "buttons"),
                                  TableExtension(kU16, "buttons2"),
                                  TableExtension(kU8, "enabled_extensions"),
                                  TableExtension(kI16, "s"),
                                  TableExtension(kI16, "t")};
  NumberedFields(manual, kI16, "aux", 1, 6, "", true);
  t.push_back(TableMessage(69, "MANUAL_CONTROL", std::move(manual)));
  t.push_back(TableMessage(
      74, "VFR_HUD",
      {TableField(kF, "airspeed"), TableField(kF, "groundspeed"), TableField(kI16, "heading"),
       TableField(kU16, "throttle"), TableField(kF, "alt"), TableField(kF, "climb")}));
  std::vector<FieldDef> command = {TableField(kU8, "target_system"),
                                   TableField(kU8, "target_component"), TableField(kU16, "command"),
                                   TableField(kU8, "confirmation")};
  NumberedFields(command, kF, "param", 1, 7, "", false);
  t.push_back(TableMessage(76, "COMMAND_LONG", std::move(command)));
  t.push_back(TableMessage(
      77, "COMMAND_ACK",
      {TableField(kU16, "command"), TableField(kU8, "result"), TableExtension(kU8, "progress"),
       TableExtension(kI32, "result_param2"), TableExtension(kU8, "target_system"),
       TableExtension(kU8, "target_component")}));
  t.push_back(TableMessage(
      83, "ATTITUDE_TARGET",
      {TableField(kU32, "time_boot_ms"), TableField(kU8, "type_mask"), TableField(kF, "q", 4),
       TableField(kF, "body_roll_rate"), TableField(kF, "body_pitch_rate"),
       TableField(kF, "body_yaw_rate"), TableField(kF, "thrust")}));
  t.push_back(TableMessage(
      105, "HIGHRES_IMU",
      {TableField(kU64, "time_usec"), TableField(kF, "xacc"), TableField(kF, "yacc"),
       TableField(kF, "zacc"), TableField(kF, "xgyro"), TableField(kF, "ygyro"),
       TableField(kF, "zgyro"), TableField(kF, "xmag"), TableField(kF, "ymag"),
       TableField(kF, "zmag"), TableField(kF, "abs_pressure"), TableField(kF, "diff_pressure"),
       TableField(kF, "pressure_alt"), TableField(kF, "temperature"),
       TableField(kU16, "fields_updated"), TableExtension(kU8, "id")}));
  t.push_back(TableMessage(
      375, "ACTUATOR_OUTPUT_STATUS",
      {TableField(kU64, "time_usec"), TableField(kU32, "active"), TableField(kF, "actuator", 32)}));
  return t;
}

std::vector<MessageDef> BuildTable() {
  std::vector<MessageDef> t = TableRows();
  for (MessageDef& m : t) {
    m.wire = WireLayout(m);
    m.base_length = 0;
    m.length = 0;
    for (const FieldDef& f : m.fields) {
      if (!f.extension) m.base_length += f.size();
      m.length += f.size();
    }
    m.crc_extra = CrcExtra(m);
  }
  std::sort(t.begin(), t.end(),
            [](const MessageDef& a, const MessageDef& b) { return a.id < b.id; });
  return t;
}

// "actuator[1]" → ("actuator", 1); "pitch" → ("pitch", nullopt); nullopt for a malformed index.
std::optional<std::pair<std::string_view, std::optional<std::size_t>>> SplitElement(
    std::string_view name) {
  const std::size_t open = name.find('[');
  if (open == std::string_view::npos) return std::pair{name, std::optional<std::size_t>()};
  if (name.back() != ']' || open + 2 >= name.size()) return std::nullopt;
  std::size_t index = 0;
  for (std::size_t i = open + 1; i + 1 < name.size(); ++i) {
    const char c = name[i];
    if (c < '0' || c > '9' || index > 1000) return std::nullopt;
    index = index * 10 + static_cast<std::size_t>(c - '0');
  }
  return std::pair{name.substr(0, open), std::optional<std::size_t>(index)};
}

}  // namespace

std::size_t SizeOf(FieldType type) {
  switch (type) {
    case FieldType::kChar:
    case FieldType::kInt8:
    case FieldType::kUint8:
      return 1;
    case FieldType::kInt16:
    case FieldType::kUint16:
      return 2;
    case FieldType::kInt32:
    case FieldType::kUint32:
    case FieldType::kFloat:
      return 4;
    case FieldType::kInt64:
    case FieldType::kUint64:
    case FieldType::kDouble:
      return 8;
  }
  return 1;
}

const char* TypeName(FieldType type) {
  switch (type) {
    case FieldType::kChar:
      return "char";
    case FieldType::kInt8:
      return "int8_t";
    case FieldType::kUint8:
      return "uint8_t";
    case FieldType::kInt16:
      return "int16_t";
    case FieldType::kUint16:
      return "uint16_t";
    case FieldType::kInt32:
      return "int32_t";
    case FieldType::kUint32:
      return "uint32_t";
    case FieldType::kInt64:
      return "int64_t";
    case FieldType::kUint64:
      return "uint64_t";
    case FieldType::kFloat:
      return "float";
    case FieldType::kDouble:
      return "double";
  }
  return "?";
}

std::vector<WireField> WireLayout(const MessageDef& message) {
  std::vector<FieldDef> base, extensions;
  for (const FieldDef& f : message.fields) (f.extension ? extensions : base).push_back(f);
  std::stable_sort(base.begin(), base.end(), [](const FieldDef& a, const FieldDef& b) {
    return SizeOf(a.type) > SizeOf(b.type);
  });
  std::vector<WireField> wire;
  wire.reserve(message.fields.size());
  std::size_t offset = 0;
  for (const auto* part : {&base, &extensions}) {
    for (const FieldDef& f : *part) {
      wire.push_back(WireField{f, offset});
      offset += f.size();
    }
  }
  return wire;
}

std::uint8_t CrcExtra(const MessageDef& message) {
  std::uint16_t crc = CrcAccumulate(message.name + " ", kCrcInit);
  for (const WireField& w : WireLayout(message)) {
    if (w.field.extension) continue;  // after every base field: the extensions are left out
    crc = CrcAccumulate(std::string(TypeName(w.field.type)) + " ", crc);
    crc = CrcAccumulate(w.field.name + " ", crc);
    if (w.field.array_length != 0) crc = CrcAccumulate(w.field.array_length, crc);
  }
  return static_cast<std::uint8_t>((crc & 0xFF) ^ (crc >> 8));
}

const std::vector<MessageDef>& KnownMessages() {
  static const std::vector<MessageDef> table = BuildTable();
  return table;
}

const MessageDef* FindById(std::uint32_t id) {
  const std::vector<MessageDef>& t = KnownMessages();
  const auto it = std::lower_bound(t.begin(), t.end(), id,
                                   [](const MessageDef& m, std::uint32_t v) { return m.id < v; });
  return it != t.end() && it->id == id ? &*it : nullptr;
}

const MessageDef* FindByName(std::string_view name) {
  for (const MessageDef& m : KnownMessages())
    if (m.name == name) return &m;
  return nullptr;
}

std::optional<FieldRef> FindField(const MessageDef& message, std::string_view name) {
  const auto split = SplitElement(name);
  if (!split) return std::nullopt;
  const auto& [field_name, index] = *split;
  for (const WireField& w : message.wire) {
    if (w.field.name != field_name) continue;
    if (w.field.type == FieldType::kChar) return std::nullopt;
    const bool is_array = w.field.array_length != 0;
    if (is_array != index.has_value()) return std::nullopt;
    const std::size_t element = index.value_or(0);
    if (element >= w.field.count()) return std::nullopt;
    return FieldRef{w.field.type, w.offset + element * SizeOf(w.field.type)};
  }
  return std::nullopt;
}

double ReadValue(const std::uint8_t* p, FieldType type) {
  std::uint64_t bits = 0;
  const std::size_t n = SizeOf(type);
  for (std::size_t i = n; i-- > 0;) bits = (bits << 8) | p[i];
  switch (type) {
    case FieldType::kChar:
    case FieldType::kUint8:
    case FieldType::kUint16:
    case FieldType::kUint32:
    case FieldType::kUint64:
      return static_cast<double>(bits);
    case FieldType::kInt8:
      return static_cast<double>(static_cast<std::int8_t>(static_cast<std::uint8_t>(bits)));
    case FieldType::kInt16:
      return static_cast<double>(static_cast<std::int16_t>(static_cast<std::uint16_t>(bits)));
    case FieldType::kInt32:
      return static_cast<double>(static_cast<std::int32_t>(static_cast<std::uint32_t>(bits)));
    case FieldType::kInt64:
      return static_cast<double>(static_cast<std::int64_t>(bits));
    case FieldType::kFloat: {
      const auto u = static_cast<std::uint32_t>(bits);
      float f;
      std::memcpy(&f, &u, sizeof f);
      return static_cast<double>(f);
    }
    case FieldType::kDouble: {
      double d;
      std::memcpy(&d, &bits, sizeof d);
      return d;
    }
  }
  return 0.0;
}

}  // namespace odonata::mavlink

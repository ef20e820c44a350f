#include "mavlink/frame_encoder.hpp"

#include <cmath>
#include <cstring>
#include <optional>
#include <stdexcept>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/mavlink_crc.hpp"

namespace odonata::mavlink {
namespace {

// `value` as `type`'s little-endian bytes at `p` (ReadValue's inverse).
void WriteValue(std::uint8_t* p, FieldType type, double value) {
  std::uint64_t bits = 0;
  switch (type) {
    case FieldType::kFloat: {
      const auto f = static_cast<float>(value);
      std::uint32_t u;
      std::memcpy(&u, &f, sizeof u);
      bits = u;
      break;
    }
    case FieldType::kDouble:
      std::memcpy(&bits, &value, sizeof bits);
      break;
    case FieldType::kInt8:
    case FieldType::kInt16:
    case FieldType::kInt32:
    case FieldType::kInt64:
      bits = static_cast<std::uint64_t>(static_cast<std::int64_t>(value));
      break;
    default:
      bits = static_cast<std::uint64_t>(value);
      break;
  }
  for (std::size_t i = 0; i < SizeOf(type); ++i) p[i] = static_cast<std::uint8_t>(bits >> (8 * i));
}

}  // namespace

PayloadBuilder::PayloadBuilder(const MessageDef& message)
    : message_(message), bytes_(message.length, '\0') {}

PayloadBuilder& PayloadBuilder::Set(std::string_view field, double value) {
  const std::optional<FieldRef> ref = FindField(message_, field);
  if (!ref) throw std::invalid_argument(message_.name + " has no field " + std::string(field));
  if (!std::isfinite(value) && ref->type != FieldType::kFloat && ref->type != FieldType::kDouble)
    throw std::invalid_argument(message_.name + "." + std::string(field) + " cannot hold " +
                                std::to_string(value));
  WriteValue(reinterpret_cast<std::uint8_t*>(bytes_.data()) + ref->offset, ref->type, value);
  return *this;
}

std::string EncodeFrameV2(const MessageDef& message, std::string_view payload, std::uint8_t seq,
                          std::uint8_t sysid, std::uint8_t compid) {
  while (payload.size() > 1 && payload.back() == '\0') payload.remove_suffix(1);
  std::string frame = {static_cast<char>(kStartV2),
                       static_cast<char>(payload.size()),
                       '\0',
                       '\0',
                       static_cast<char>(seq),
                       static_cast<char>(sysid),
                       static_cast<char>(compid),
                       static_cast<char>(message.id & 0xFF),
                       static_cast<char>((message.id >> 8) & 0xFF),
                       static_cast<char>((message.id >> 16) & 0xFF)};
  frame.append(payload);
  std::uint16_t crc = CrcAccumulate(std::string_view(frame).substr(1), kCrcInit);
  crc = CrcAccumulate(message.crc_extra, crc);
  frame += static_cast<char>(crc & 0xFF);
  frame += static_cast<char>(crc >> 8);
  return frame;
}

std::string SetMessageIntervalPayload(std::uint8_t target_system, std::uint8_t target_component,
                                      std::uint32_t message_id, double interval_us) {
  const MessageDef* command = FindByName("COMMAND_LONG");
  PayloadBuilder p(*command);
  p.Set("target_system", target_system)
      .Set("target_component", target_component)
      .Set("command", kCmdSetMessageInterval)
      .Set("param1", static_cast<double>(message_id))
      .Set("param2", interval_us);
  return p.bytes();
}

}  // namespace odonata::mavlink

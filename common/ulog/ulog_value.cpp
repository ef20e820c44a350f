#include "ulog/ulog_value.hpp"

#include <limits>

namespace odonata::ulog {
namespace {

struct ValueShape {
  std::optional<BasicType> basic;
  bool is_array = false;
};

// Only the element type and whether there is a "[N]": a joined multi-info value may be longer
// than one message (ParseTypeRef's limit), and a value made by hand need not be well formed.
ValueShape ShapeOf(std::string_view type) {
  const auto open = type.find('[');
  return ValueShape{ParseBasicType(type.substr(0, open)), open != std::string_view::npos};
}

}  // namespace

bool TypedValue::IsText() const {
  const auto basic = ShapeOf(type).basic;
  return basic && *basic == BasicType::kChar;
}

std::string TypedValue::Text() const {
  std::string s = bytes;
  while (!s.empty() && s.back() == '\0') s.pop_back();
  return s;
}

std::optional<double> TypedValue::Number() const {
  const ValueShape shape = ShapeOf(type);
  if (!shape.basic || shape.is_array || *shape.basic == BasicType::kChar) return std::nullopt;
  if (bytes.size() != SizeOf(*shape.basic)) return std::nullopt;
  return ReadAsDouble(reinterpret_cast<const std::uint8_t*>(bytes.data()), *shape.basic);
}

std::optional<std::int64_t> TypedValue::Integer() const {
  const ValueShape shape = ShapeOf(type);
  if (!shape.basic || shape.is_array) return std::nullopt;
  const BasicType t = *shape.basic;
  if (t == BasicType::kFloat || t == BasicType::kDouble || t == BasicType::kChar)
    return std::nullopt;
  const std::size_t n = SizeOf(t);
  if (bytes.size() != n) return std::nullopt;
  const std::uint64_t raw = ReadUnsignedLE(reinterpret_cast<const std::uint8_t*>(bytes.data()), n);
  switch (t) {
    case BasicType::kInt8:
      return static_cast<std::int8_t>(raw);
    case BasicType::kInt16:
      return static_cast<std::int16_t>(raw);
    case BasicType::kInt32:
      return static_cast<std::int32_t>(raw);
    case BasicType::kInt64:
      return static_cast<std::int64_t>(raw);
    case BasicType::kBool:
      return raw != 0 ? 1 : 0;
    case BasicType::kUint64:
      if (raw > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
        return std::nullopt;
      return static_cast<std::int64_t>(raw);
    default:
      return static_cast<std::int64_t>(raw);
  }
}

NamedValue ParseNamedValue(std::string_view key, std::string_view bytes) {
  const auto blank = key.find(' ');
  if (blank == std::string_view::npos || blank == 0 || blank + 1 == key.size())
    throw UlogError("key '" + std::string(key) + "' is not 'type name'");
  NamedValue v;
  v.name = std::string(key.substr(blank + 1));
  v.value.type = std::string(key.substr(0, blank));
  v.value.bytes = std::string(bytes);
  const TypeRef t = ParseTypeRef(v.value.type);
  const auto basic = ParseBasicType(t.name);
  if (basic && *basic != BasicType::kChar && bytes.size() != SizeOf(*basic) * t.count())
    throw UlogError("value of '" + std::string(key) + "' has " + std::to_string(bytes.size()) +
                    " bytes, its type " + std::to_string(SizeOf(*basic) * t.count()));
  return v;
}

void AppendContinuation(TypedValue& value, std::string_view more_bytes) {
  value.bytes.append(more_bytes.data(), more_bytes.size());
  const ValueShape shape = ShapeOf(value.type);
  if (shape.is_array && shape.basic && value.bytes.size() % SizeOf(*shape.basic) == 0)
    value.type = std::string(TypeName(*shape.basic)) + "[" +
                 std::to_string(value.bytes.size() / SizeOf(*shape.basic)) + "]";
}

}  // namespace odonata::ulog

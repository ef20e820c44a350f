#pragma once
// The type system of a PX4 ULog file: the basic types, the 'F' messages that combine them into
// formats (nested types, fixed arrays, padding), and the flat layout of a subscribed format, every
// field at its byte offset, with which the data messages are read.

#include <cstddef>
#include <cstdint>
#include <map>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::ulog {

/// Raised for a file that cannot be read as ULog at all (no such file, bad magic), by the strict
/// entry points for any damage, and by the format functions below for a malformed definition.
class UlogError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The largest payload a message can carry: its size is a uint16_t.
inline constexpr std::size_t kMaxMessagePayload = 65535;

enum class BasicType : std::uint8_t {
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
  kBool,
  kChar,
};

/// The basic type called `name` ("int8_t" … "uint64_t", "float", "double", "bool", "char").
std::optional<BasicType> ParseBasicType(std::string_view name);
std::size_t SizeOf(BasicType type);
/// The C name, as the file writes it ("float", "uint8_t").
const char* TypeName(BasicType type);

/// A type as a format or a key names it: "float", "float[4]", "esc_report[8]".
struct TypeRef {
  std::string name;                         ///< a basic type or the name of another format
  std::optional<std::size_t> array_length;  ///< set for "name[N]" (N may be 0)
  std::size_t count() const { return array_length.value_or(1); }
};
/// Parses "name" or "name[N]". @throws UlogError saying what is wrong.
TypeRef ParseTypeRef(std::string_view text);

struct FormatField {
  TypeRef type;
  std::string name;
  /// Fields named "_padding…" only align the others: a reader skips their bytes.
  bool IsPadding() const { return name.rfind("_padding", 0) == 0; }
};

/// One 'F' message: "name:type field;type[N] field;…".
struct Format {
  std::string name;
  std::vector<FormatField> fields;
};
/// @throws UlogError for a text that is not a format (no ':', no field, a field without a type or
///   name, a name with characters that would make signal names ambiguous, a field twice).
Format ParseFormat(std::string_view text);

/// One field of a flattened layout. Nested formats are expanded ("inner.x", "inner[2].x"); arrays
/// of a basic type stay one field of `count` elements, `element_size` bytes apart.
struct FieldLayout {
  std::string path;
  BasicType type = BasicType::kUint8;
  std::size_t offset = 0;  ///< of the first element, from the start of the message's data
  std::size_t count = 1;   ///< elements: the N of "float[N]", 1 for a scalar
  bool is_array = false;   ///< declared as "type[N]" (even N = 1), so names carry "[i]"
};

/// The flat layout of a subscribed format: what every one of its data messages holds.
struct Layout {
  std::string name;
  std::vector<FieldLayout> fields;  ///< in declaration order, padding left out
  std::size_t size = 0;             ///< bytes, padding included
  /// Bytes a data message must at least hold: `size` without the padding at the very end, which
  /// the logger does not write (padding inside nested formats stays).
  std::size_t logged_size = 0;
  std::size_t timestamp_offset = 0;  ///< of the top-level "uint64_t timestamp" field

  /// The field called `path` ("timestamp", "inner.x", "q"), or nullptr.
  const FieldLayout* Find(std::string_view path) const;
};

/// Flattens format `name`, whose nested types are looked up in `formats`. A subscribed format must
/// hold a top-level uint64_t "timestamp" (microseconds). `field_budget` is decreased by the
/// fields made and bounds the work a hostile file can cause (a 1-byte type in a 60000-element
/// nested array, formats nested 32 deep).
/// @throws UlogError for an unknown type, a cycle, nesting deeper than 32, a layout larger than a
///   message can hold, no timestamp, or an exhausted budget.
Layout ResolveLayout(const std::string& name, const std::map<std::string, Format>& formats,
                     std::size_t& field_budget);

/// A little-endian value of `type` at `p` as a double (bool as 0/1, 64-bit integers rounded to
/// the nearest double above 2^53). `p` must point at SizeOf(type) readable bytes; no alignment is
/// needed.
double ReadAsDouble(const std::uint8_t* p, BasicType type);

/// A little-endian unsigned integer of `bytes` bytes at `p` (1 to 8), independent of the host.
inline std::uint64_t ReadUnsignedLE(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = bytes; i-- > 0;) v = (v << 8) | p[i];
  return v;
}

}  // namespace odonata::ulog

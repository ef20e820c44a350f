#pragma once
// The record layout of an ArduPilot DataFlash log (ArduPilot's LogStructure.h): the format
// characters an FMT record combines into a message, each field at its byte offset, and a field's
// value read from a record's payload.
//
// A record is 0xA3 0x95, the message type (uint8), then the payload, little-endian; the FMT record
// of a type gives its whole length (header included), its name, format characters and
// comma-separated column labels. FMT itself is type 128, 89 bytes: "BBnNZ"
// "Type,Length,Name,Format,Columns".

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::dataflash {

/// Raised for bytes that are no DataFlash log at all (or a file that cannot be read): damage
/// inside a log is reported in DataflashFile::problem instead.
class DataflashError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

inline constexpr std::uint8_t kRecordHead1 = 0xA3;
inline constexpr std::uint8_t kRecordHead2 = 0x95;
inline constexpr std::size_t kRecordHeaderSize = 3;  ///< the two head bytes and the type
inline constexpr std::uint8_t kFmtType = 128;
inline constexpr std::size_t kFmtLength = 89;  ///< an FMT record, header included

enum class FieldKind : std::uint8_t {
  kInteger,     ///< b B h H i I q Q, and the scaled c C e E L and the flight mode M
  kFloat,       ///< f d
  kText,        ///< n N Z: char[4], char[16], char[64], NUL-padded
  kInt16Array,  ///< a: int16_t[32]
};

/// What one format character stands for.
struct FormatChar {
  std::size_t size = 0;  ///< bytes it takes in the payload
  FieldKind kind = FieldKind::kInteger;
  bool is_signed = false;
  /// The logged number times this is the value, as pymavlink reads it: 0.01 for c C e E
  /// (centi-units), 1e-7 for L (degrees of latitude or longitude), 1 for the others.
  double scale = 1.0;
};

/// The format character `c`, or nullopt for one that LogStructure.h does not define.
std::optional<FormatChar> LookupFormatChar(char c);

struct Field {
  std::string label;       ///< its column ("" where the FMT gives fewer labels than characters)
  char type = 0;           ///< its format character
  std::size_t offset = 0;  ///< of its first byte, from the start of the payload
  std::size_t count = 1;   ///< elements: 32 for 'a', 1 for every other character
};

/// One FMT record: how the records of one message type are laid out.
struct MessageFormat {
  std::uint8_t type = 0;
  std::string name;                 ///< up to 4 characters: "ATT", "IMU", "RCOU"
  std::size_t length = 0;           ///< of a whole record, the 3-byte header included (>= 3)
  std::string format;               ///< one character per field: "QccccCCCC"
  std::vector<std::string> labels;  ///< the columns, in order: "TimeUS", "DesRoll", …
  /// One per format character, in order; empty when the records cannot be decoded.
  std::vector<Field> fields;
  /// Why the fields cannot be read ("" when they can): an unknown format character, or more
  /// bytes than the length gives. Such records are still framed and counted.
  std::string undecodable;
  std::uint64_t defined_at = 0;  ///< byte offset of its FMT record

  std::size_t payload_size() const { return length - kRecordHeaderSize; }
  bool decodable() const { return undecodable.empty(); }
  /// The index of the first field labelled `label`, or nullopt.
  std::optional<std::size_t> IndexOf(std::string_view label) const;
};

/// The format of the fields of an FMT record; `labels` is its comma-separated column list. Bytes
/// the characters leave unused at the end of the payload are ignored, as pymavlink does.
/// @pre length >= kRecordHeaderSize
MessageFormat MakeFormat(std::uint8_t type, std::string_view name, std::size_t length,
                         std::string_view format, std::string_view labels);

/// The built-in format of FMT records (type 128), which every log starts with.
MessageFormat FmtFormat();

/// A char[] field's bytes up to the first NUL.
std::string CString(std::string_view chars);

/// Element `element` of numeric `field` in `payload`, the logged number unscaled (64-bit integers
/// above 2^53 rounded to the nearest double).
/// @pre field is no text, element < field.count, and payload holds field.offset + its size bytes.
double RawValue(const std::uint8_t* payload, const Field& field, std::size_t element = 0);

/// The text of char field `field` (n, N, Z) in `payload`, up to its first NUL.
/// @pre payload holds the field.
std::string FieldText(const std::uint8_t* payload, const Field& field);

/// A little-endian unsigned integer of `bytes` bytes at `p` (1 to 8), independent of the host.
inline std::uint64_t ReadUnsignedLE(const std::uint8_t* p, std::size_t bytes) {
  std::uint64_t v = 0;
  for (std::size_t i = bytes; i-- > 0;) v = (v << 8) | p[i];
  return v;
}

}  // namespace odonata::dataflash

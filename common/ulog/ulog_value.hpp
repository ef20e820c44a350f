#pragma once
// The typed key/value pairs of a ULog file's information ('I', 'M') and parameter ('P', 'Q')
// messages: a key "type name" ("char[7] sys_name", "int32_t MC_ROLL_P") and the value's bytes.

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

#include "ulog/ulog_format.hpp"

namespace odonata::ulog {

/// A value as the file holds it: its declared type and its bytes, unchanged.
struct TypedValue {
  std::string type;   ///< "char[7]", "int32_t", "float[3]", or the name of a format
  std::string bytes;  ///< little-endian, exactly as in the file

  /// A char array (or one char): text.
  bool IsText() const;
  /// The bytes as text, without trailing NULs (ULog strings carry none, some writers pad).
  std::string Text() const;
  /// A scalar of a basic numeric type (bool included) as a double; nullopt for text, arrays and
  /// nested types.
  std::optional<double> Number() const;
  /// A scalar integer (bool included), exactly; nullopt otherwise and for a uint64_t above
  /// INT64_MAX.
  std::optional<std::int64_t> Integer() const;
};

struct NamedValue {
  std::string name;
  TypedValue value;
};

/// Splits `key` ("type name") and checks that `bytes` fit the type: a scalar or an array of a
/// basic type must have exactly its size; a char array may be of any length (writers have sized
/// the key's N and the value differently); a nested type is kept as bytes.
/// @throws UlogError saying what does not fit.
NamedValue ParseNamedValue(std::string_view key, std::string_view bytes);

/// Appends a continuation (an 'M' message with is_continued set) to `value`: the bytes are
/// concatenated, and an array type's length becomes the joined length ("char[40]" + "char[2]" →
/// "char[42]").
void AppendContinuation(TypedValue& value, std::string_view more_bytes);

}  // namespace odonata::ulog

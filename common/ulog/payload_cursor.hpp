#pragma once
// Reading one ULog message's payload, field by field, each checked against what is left of it
// (ulog_file.cpp's walk over the messages): internal to ulog/.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

#include "ulog/ulog_format.hpp"
#include "ulog/ulog_value.hpp"

namespace odonata::ulog {

// A message that cannot be read: the walk stops there and reports `what` at its offset.
struct MessageDamage {
  std::string what;
};

// The fields of one message's payload, each checked against what is left of it.
class PayloadCursor {
 public:
  explicit PayloadCursor(std::string_view payload) : payload_(payload) {}

  std::uint8_t U8(const char* what) { return static_cast<std::uint8_t>(Unsigned(1, what)); }
  std::uint16_t U16(const char* what) { return static_cast<std::uint16_t>(Unsigned(2, what)); }
  std::uint64_t U64(const char* what) { return Unsigned(8, what); }
  std::string_view Take(std::size_t n, const char* what) {
    Need(n, what);
    const std::string_view s = payload_.substr(at_, n);
    at_ += n;
    return s;
  }
  std::string_view Rest() {
    const std::string_view s = payload_.substr(at_);
    at_ = payload_.size();
    return s;
  }

 private:
  std::uint64_t Unsigned(std::size_t n, const char* what) {
    Need(n, what);
    const std::uint64_t v =
        ReadUnsignedLE(reinterpret_cast<const std::uint8_t*>(payload_.data()) + at_, n);
    at_ += n;
    return v;
  }
  void Need(std::size_t n, const char* what) const {
    if (n > payload_.size() - at_)
      throw MessageDamage{std::string(what) + " needs " + std::to_string(n) + " bytes at byte " +
                          std::to_string(at_) + " of the " + std::to_string(payload_.size()) +
                          "-byte payload"};
  }

  std::string_view payload_;
  std::size_t at_ = 0;
};

// A key/value message's key ("type name") and value, checked; its problems become damage.
inline NamedValue TakeNamedValue(PayloadCursor& in) {
  const std::uint8_t key_len = in.U8("the key length");
  const std::string_view key = in.Take(key_len, "the key");
  try {
    return ParseNamedValue(key, in.Rest());
  } catch (const UlogError& e) {
    throw MessageDamage{e.what()};
  }
}

inline void RequireNumber(const NamedValue& v) {
  if (!v.value.Number())
    throw MessageDamage{"parameter '" + v.name + "' is of type " + v.value.type +
                        "; parameters are numbers (int32_t or float)"};
}

}  // namespace odonata::ulog

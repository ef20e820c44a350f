#pragma once
// Reading a micro-SD log's header field by field, each checked against what is left of the file
// (usd_log_file.cpp's walk over the event type declarations): internal to crazyflie_usd/.

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>

namespace odonata::crazyflie_usd {

/// Little-endian unsigned integer of `n` (at most 8) bytes at `p`.
inline std::uint64_t ReadUnsignedLE(const unsigned char* p, std::size_t n) {
  std::uint64_t v = 0;
  for (std::size_t i = n; i > 0; --i) v = (v << 8) | p[i - 1];
  return v;
}

/// `text` fit for a message: non-printable bytes as \xNN, cut after 60 characters.
inline std::string Printable(std::string_view text) {
  static const char kHex[] = "0123456789abcdef";
  std::string s;
  for (std::size_t i = 0; i < text.size() && i < 60; ++i) {
    const auto c = static_cast<unsigned char>(text[i]);
    if (c >= 0x20 && c < 0x7f) {
      s += static_cast<char>(c);
    } else {
      s += "\\x";
      s += kHex[c >> 4];
      s += kHex[c & 0xfu];
    }
  }
  if (text.size() > 60) s += "...";
  return s;
}

/// Bytes that cannot be read as what the format puts there: the walk stops at `offset`.
struct CursorDamage {
  std::size_t offset = 0;
  std::string what;
};

/// The fields of the bytes from a position on, each checked against what is left of them.
class ByteCursor {
 public:
  ByteCursor(std::string_view bytes, std::size_t at) : bytes_(bytes), at_(at) {}

  std::size_t at() const { return at_; }
  std::size_t left() const { return bytes_.size() - at_; }

  std::uint16_t U16(std::string_view what) { return static_cast<std::uint16_t>(Unsigned(2, what)); }

  /// A NUL-terminated string of at most `max_length` bytes, its NUL consumed.
  std::string_view CString(std::string_view what, std::size_t max_length) {
    const std::size_t nul = bytes_.find('\0', at_);
    if (nul == std::string_view::npos)
      throw CursorDamage{at_, "the file ends inside " + std::string(what) + " at byte " +
                                  std::to_string(at_) + " (no terminating NUL in the " +
                                  std::to_string(left()) + " bytes left): the header is cut"};
    if (nul - at_ > max_length)
      throw CursorDamage{at_, std::string(what) + " at byte " + std::to_string(at_) + " is " +
                                  std::to_string(nul - at_) + " bytes long ('" +
                                  Printable(bytes_.substr(at_, nul - at_)) +
                                  "'); Crazyflie names are short, this reader refuses over " +
                                  std::to_string(max_length)};
    const std::string_view s = bytes_.substr(at_, nul - at_);
    at_ = nul + 1;
    return s;
  }

 private:
  std::uint64_t Unsigned(std::size_t n, std::string_view what) {
    if (n > left())
      throw CursorDamage{at_, "the file ends inside " + std::string(what) + " at byte " +
                                  std::to_string(at_) + " (" + std::to_string(n) +
                                  " bytes needed, " + std::to_string(left()) +
                                  " left): the header is cut"};
    const std::uint64_t v =
        ReadUnsignedLE(reinterpret_cast<const unsigned char*>(bytes_.data()) + at_, n);
    at_ += n;
    return v;
  }

  std::string_view bytes_;
  std::size_t at_ = 0;
};

}  // namespace odonata::crazyflie_usd

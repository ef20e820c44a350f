#pragma once
// A read-only cursor over LCM's wire format, for the CountsFit walkers that
// lcmtypes/gen_wire_bounds.py generates from the .lcm files (bus/wire_bounds.cpp in the build
// tree). Big-endian; a string is an int32 length that counts its NUL, then the bytes; a nested
// struct is inline, without a fingerprint. Every read fails once the buffer is exhausted or a
// count is absurd, so a walker can chain reads and test ok() at the end.

#include <cstdint>
#include <initializer_list>
#include <type_traits>

namespace odonata::bus {

class WireCursor {
 public:
  WireCursor(const void* data, int64_t size)
      : data_(static_cast<const uint8_t*>(data)), size_(data ? size : -1) {}

  bool ok() const { return ok_; }

  void Skip(int64_t bytes) {
    if (!ok_ || bytes < 0 || bytes > size_ - pos_) {
      ok_ = false;
      return;
    }
    pos_ += bytes;
  }

  // Reads an integer field (int8_t … int64_t) that sizes an array: negative counts (decode()
  // would resize to ~2^64) and counts larger than the whole message (no element takes less than
  // a byte, but an array of empty rows takes none, so the remaining bytes alone are no bound) are
  // rejected.
  template <class Int>
  int64_t Count() {
    const int64_t n = Read<Int>();
    if (n < 0 || n > size_) ok_ = false;
    return ok_ ? n : 0;
  }

  // decode() assigns length − 1 characters: a length of 0 would ask for 2^64 − 1.
  void String() {
    const int64_t length = Count<int32_t>();
    if (length < 1) ok_ = false;
    Skip(length);
  }

  void Strings(int64_t n) {
    for (int64_t i = 0; i < n && ok_; ++i) String();
  }

  // The elements of an array whose dimensions are `dims`, outermost first. decode() resizes one
  // vector per row before it reads a byte, and rows of nothing take no bytes, so the rows at every
  // level, not only the elements, must stay within the message's size, as a single count does.
  int64_t Elements(std::initializer_list<int64_t> dims) {
    int64_t n = 1;
    for (const int64_t d : dims) {
      if (!ok_ || d < 0 || (d > 0 && n > size_ / d)) {
        ok_ = false;
        return 0;
      }
      n *= d;
    }
    return n;
  }

  // `n` elements of `bytes` each, with the product checked against the remaining bytes.
  void Array(int64_t n, int64_t bytes) {
    if (ok_ && bytes > 0 && n > (size_ - pos_) / bytes) ok_ = false;
    if (ok_) Skip(n * bytes);
  }

 private:
  template <class Int>
  int64_t Read() {
    static_assert(std::is_integral_v<Int> && std::is_signed_v<Int> && sizeof(Int) <= 8);
    constexpr int64_t kBytes = sizeof(Int);
    if (!ok_ || size_ - pos_ < kBytes) {
      ok_ = false;
      return 0;
    }
    uint64_t v = 0;
    for (int64_t i = 0; i < kBytes; ++i) v = (v << 8) | data_[pos_ + i];
    pos_ += kBytes;
    return static_cast<Int>(static_cast<std::make_unsigned_t<Int>>(v));
  }

  const uint8_t* data_;
  int64_t size_;
  int64_t pos_ = 0;
  bool ok_ = size_ >= 0;
};

}  // namespace odonata::bus

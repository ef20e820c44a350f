#pragma once
// A small Crazyflie micro-SD log writer for the tests: the header, records and CRC32 trailer laid
// out as the firmware's usddeck.c writes them (little-endian, no padding), and damaged ones too
// (raw bytes, a wrong CRC). Its CRC is computed bit by bit, apart from the reader's table.

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::crazyflie_usd::testing {

/// zlib's CRC32, one bit at a time.
inline std::uint32_t BitwiseCrc32(std::string_view bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

inline void PutLE(std::string& out, std::uint64_t v, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) out += static_cast<char>((v >> (8 * i)) & 0xffu);
}

/// The packed values of one record, in declared order.
class Packed {
 public:
  Packed& U8(std::uint8_t v) { return Put(v, 1); }
  Packed& I8(std::int8_t v) { return Put(static_cast<std::uint8_t>(v), 1); }
  Packed& U16(std::uint16_t v) { return Put(v, 2); }
  Packed& I16(std::int16_t v) { return Put(static_cast<std::uint16_t>(v), 2); }
  Packed& U32(std::uint32_t v) { return Put(v, 4); }
  Packed& I32(std::int32_t v) { return Put(static_cast<std::uint32_t>(v), 4); }
  Packed& F32(float v) {
    std::uint32_t bits;
    std::memcpy(&bits, &v, sizeof bits);
    return Put(bits, 4);
  }
  Packed& Half(std::uint16_t bits) { return Put(bits, 2); }
  const std::string& bytes() const { return bytes_; }

 private:
  Packed& Put(std::uint64_t v, std::size_t n) {
    PutLE(bytes_, v, n);
    return *this;
  }
  std::string bytes_;
};

struct Declaration {
  std::uint16_t id = 0;
  std::string name;
  std::vector<std::string> variables;  ///< as written: "gyro.x(f)"
};

class UsdLogWriter {
 public:
  UsdLogWriter(std::uint16_t version, const std::vector<Declaration>& types) : version_(version) {
    bytes_ += '\xbc';
    PutLE(bytes_, version, 2);
    PutLE(bytes_, types.size(), 2);
    for (const Declaration& d : types) {
      PutLE(bytes_, d.id, 2);
      bytes_ += d.name;
      bytes_ += '\0';
      PutLE(bytes_, d.variables.size(), 2);
      for (const std::string& v : d.variables) {
        bytes_ += v;
        bytes_ += '\0';
      }
    }
    header_size_ = bytes_.size();
  }

  /// A record: u16 id, the timestamp (µs in version 2, ms in version 1), the values.
  UsdLogWriter& Record(std::uint16_t id, std::uint64_t stamp, const Packed& values = Packed()) {
    starts_.push_back(bytes_.size());
    PutLE(bytes_, id, 2);
    PutLE(bytes_, stamp, version_ == 1 ? 4 : 8);
    bytes_ += values.bytes();
    ends_.push_back(bytes_.size());
    return *this;
  }
  UsdLogWriter& Raw(std::string_view bytes) {
    bytes_ += bytes;
    return *this;
  }

  /// The file: everything written, then the CRC32 of it.
  std::string Finish() const { return FinishWithCrc(BitwiseCrc32(bytes_)); }
  std::string FinishWithCrc(std::uint32_t crc) const {
    std::string out = bytes_;
    PutLE(out, crc, 4);
    return out;
  }

  std::size_t header_size() const { return header_size_; }
  std::size_t size() const { return bytes_.size(); }                  ///< without the trailer
  const std::vector<std::size_t>& starts() const { return starts_; }  ///< of each record
  const std::vector<std::size_t>& ends() const { return ends_; }

 private:
  std::uint16_t version_;
  std::string bytes_;
  std::size_t header_size_ = 0;
  std::vector<std::size_t> starts_, ends_;
};

}  // namespace odonata::crazyflie_usd::testing

#pragma once
// CRC-16/MCRF4XX, the checksum of every MAVLink frame and of mavgen's CRC_EXTRA (MAVLink's
// checksum.h calls it X.25): polynomial 0x1021 reflected (0x8408), initial value 0xFFFF, no final
// XOR. A frame's checksum covers its bytes after the start byte, then the message's CRC_EXTRA.

#include <cstddef>
#include <cstdint>
#include <string_view>

namespace odonata::mavlink {

inline constexpr std::uint16_t kCrcInit = 0xFFFF;

/// The checksum `crc` continued over one byte (checksum.h's crc_accumulate).
inline std::uint16_t CrcAccumulate(std::uint8_t byte, std::uint16_t crc) {
  std::uint8_t tmp = static_cast<std::uint8_t>(byte ^ (crc & 0xFF));
  tmp = static_cast<std::uint8_t>(tmp ^ (tmp << 4));
  return static_cast<std::uint16_t>((crc >> 8) ^ (tmp << 8) ^ (tmp << 3) ^ (tmp >> 4));
}

/// The checksum `crc` continued over `bytes`.
inline std::uint16_t CrcAccumulate(std::string_view bytes, std::uint16_t crc) {
  for (const char c : bytes) crc = CrcAccumulate(static_cast<std::uint8_t>(c), crc);
  return crc;
}

}  // namespace odonata::mavlink

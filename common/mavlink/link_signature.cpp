#include "mavlink/link_signature.hpp"

#include <sodium.h>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "mavlink/mavlink_crc.hpp"
#include "mavlink/mavlink_messages.hpp"

namespace odonata::mavlink {

LinkKey ReadLinkKey(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("link key file " + path + ": " + std::strerror(errno));
  std::stringstream text;
  text << in.rdbuf();
  std::string hex = text.str();
  hex.erase(std::remove_if(hex.begin(), hex.end(), [](unsigned char c) { return std::isspace(c); }),
            hex.end());
  LinkKey key{};
  std::size_t bin_len = 0;
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
  if (hex.size() != 2 * key.size() ||
      sodium_hex2bin(key.data(), key.size(), hex.data(), hex.size(), nullptr, &bin_len, nullptr) !=
          0 ||
      bin_len != key.size()) {
    throw std::runtime_error("link key file " + path +
                             " must hold 64 hex digits (the 32-byte secret key; from a "
                             "ground station's passphrase: `printf %s PASSPHRASE | sha256sum`)");
  }
  return key;
}

std::array<std::uint8_t, 6> LinkSignature(const LinkKey& key, std::string_view signed_part) {
  crypto_hash_sha256_state state;
  crypto_hash_sha256_init(&state);
  crypto_hash_sha256_update(&state, key.data(), key.size());
  crypto_hash_sha256_update(&state, reinterpret_cast<const unsigned char*>(signed_part.data()),
                            signed_part.size());
  std::array<unsigned char, crypto_hash_sha256_BYTES> digest{};
  crypto_hash_sha256_final(&state, digest.data());
  std::array<std::uint8_t, 6> out{};
  std::copy_n(digest.begin(), out.size(), out.begin());
  return out;
}

FrameDecoder::SignatureCheck SignatureCheckFor(const LinkKey& key) {
  return [key](std::string_view frame) {
    if (frame.size() < kSignatureSize) return false;
    const auto expected = LinkSignature(key, frame.substr(0, frame.size() - 6));
    return std::equal(expected.begin(), expected.end(),
                      reinterpret_cast<const std::uint8_t*>(frame.data() + frame.size() - 6));
  };
}

std::uint64_t SigningTimestampNow() {
  constexpr std::int64_t kSigningEpochUnixS = 1420070400;  // 2015-01-01 00:00:00 UTC
  const auto us = std::chrono::duration_cast<std::chrono::microseconds>(
                      std::chrono::system_clock::now().time_since_epoch())
                      .count();
  return static_cast<std::uint64_t>((us - kSigningEpochUnixS * 1000000) / 10);
}

std::string SignFrameV2(std::string_view frame, const LinkKey& key, std::uint8_t link_id,
                        std::uint64_t timestamp_10us) {
  if (frame.size() < kHeaderSizeV2 + kChecksumSize ||
      static_cast<std::uint8_t>(frame[0]) != kStartV2 ||
      frame.size() != kHeaderSizeV2 + static_cast<std::uint8_t>(frame[1]) + kChecksumSize ||
      (static_cast<std::uint8_t>(frame[2]) & kIncompatSigned) != 0)
    throw std::invalid_argument("not a whole unsigned MAVLink 2 frame");
  const std::uint32_t id = static_cast<std::uint8_t>(frame[7]) |
                           static_cast<std::uint32_t>(static_cast<std::uint8_t>(frame[8])) << 8 |
                           static_cast<std::uint32_t>(static_cast<std::uint8_t>(frame[9])) << 16;
  const MessageDef* message = FindById(id);
  if (message == nullptr)
    throw std::invalid_argument("message id " + std::to_string(id) + " is not in the table");
  std::string out(frame.substr(0, frame.size() - kChecksumSize));
  out[2] = static_cast<char>(static_cast<std::uint8_t>(out[2]) | kIncompatSigned);
  std::uint16_t crc = CrcAccumulate(std::string_view(out).substr(1), kCrcInit);
  crc = CrcAccumulate(message->crc_extra, crc);
  out += static_cast<char>(crc & 0xFF);
  out += static_cast<char>(crc >> 8);
  out += static_cast<char>(link_id);
  for (int i = 0; i < 6; ++i) out += static_cast<char>((timestamp_10us >> (8 * i)) & 0xFF);
  const auto signature = LinkSignature(key, out);
  out.append(reinterpret_cast<const char*>(signature.data()), signature.size());
  return out;
}

}  // namespace odonata::mavlink

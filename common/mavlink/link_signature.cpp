#include "mavlink/link_signature.hpp"

#include <sodium.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

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

}  // namespace odonata::mavlink

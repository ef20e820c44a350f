#include "bus/message_signer.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cctype>
#include <cstring>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace odonata::bus {
namespace {

constexpr uint8_t kMagic[4] = {'O', 'S', 'G', '1'};
constexpr std::size_t kHeaderBytes = 20;  // magic, sender id, timestamp: what the tag also covers
constexpr std::size_t kTagBytes = crypto_generichash_BYTES;
static_assert(kHeaderBytes + kTagBytes == kSignatureBytes);

void InitSodium() {
  if (sodium_init() < 0) throw std::runtime_error("libsodium could not be initialised");
}

void PutBigEndian(uint64_t v, uint8_t* out) {
  for (int i = 7; i >= 0; --i) {
    out[i] = static_cast<uint8_t>(v & 0xff);
    v >>= 8;
  }
}

uint64_t GetBigEndian(const uint8_t* in) {
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v = (v << 8) | in[i];
  return v;
}

}  // namespace

BusKey LoadBusKey(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0)
    throw std::runtime_error("key file " + path + ": " + std::strerror(errno));
  if ((st.st_mode & (S_IRWXG | S_IRWXO)) != 0) {
    throw std::runtime_error("key file " + path +
                             " may be read by others than its owner: chmod 600 it (a shared key "
                             "others can read protects nothing)");
  }
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  std::string hex = text.str();
  hex.erase(std::remove_if(hex.begin(), hex.end(), [](unsigned char c) { return std::isspace(c); }),
            hex.end());
  BusKey key;
  std::size_t bin_len = 0;
  if (!in || hex.size() != 2 * key.bytes.size() ||
      sodium_hex2bin(key.bytes.data(), key.bytes.size(), hex.data(), hex.size(), nullptr, &bin_len,
                     nullptr) != 0 ||
      bin_len != key.bytes.size()) {
    throw std::runtime_error("key file " + path +
                             " must hold 64 hex digits (32 bytes), e.g. from odonata-run or "
                             "`od -An -tx1 -N32 /dev/urandom | tr -d ' \\n'`");
  }
  return key;
}

std::string NewBusKeyHex() {
  InitSodium();
  BusKey key;
  randombytes_buf(key.bytes.data(), key.bytes.size());
  std::string hex(2 * key.bytes.size() + 1, '\0');
  sodium_bin2hex(hex.data(), hex.size(), key.bytes.data(), key.bytes.size());
  hex.pop_back();
  return hex;
}

uint64_t RandomSenderId() {
  InitSodium();
  uint64_t id = 0;
  randombytes_buf(&id, sizeof id);
  return id;
}

MessageSigner::MessageSigner(const BusKey& key, uint64_t sender_id, int64_t started_us)
    : sender_id_(sender_id), not_before_us_(started_us > 0 ? started_us : 0) {
  InitSodium();
  crypto_generichash_init(&keyed_, key.bytes.data(), key.bytes.size(), kTagBytes);
}

void MessageSigner::Tag(const std::string& channel, const uint8_t* payload,
                        std::size_t payload_size, const uint8_t* header, uint8_t* tag) const {
  crypto_generichash_state st = keyed_;
  // The channel's terminating zero keeps "AB"+"C…" and "A"+"BC…" apart.
  crypto_generichash_update(&st, reinterpret_cast<const unsigned char*>(channel.c_str()),
                            channel.size() + 1);
  crypto_generichash_update(&st, payload, payload_size);
  crypto_generichash_update(&st, header, kHeaderBytes);
  crypto_generichash_final(&st, tag, kTagBytes);
}

void MessageSigner::Sign(const std::string& channel, std::vector<uint8_t>* payload,
                         int64_t now_us) {
  last_stamp_ = std::max(now_us, last_stamp_ + 1);
  const std::size_t n = payload->size();
  payload->resize(n + kSignatureBytes);
  uint8_t* trailer = payload->data() + n;
  std::memcpy(trailer, kMagic, 4);
  PutBigEndian(sender_id_, trailer + 4);
  PutBigEndian(static_cast<uint64_t>(last_stamp_), trailer + 12);
  Tag(channel, payload->data(), n, trailer, trailer + kHeaderBytes);
}

MessageSigner::Verdict MessageSigner::Verify(const std::string& channel, const uint8_t* data,
                                             std::size_t size, int64_t now_us,
                                             std::size_t* payload_size) {
  if (size < kSignatureBytes || std::memcmp(data + size - kSignatureBytes, kMagic, 4) != 0)
    return Verdict::kUnsigned;
  const std::size_t n = size - kSignatureBytes;
  const uint8_t* trailer = data + n;
  uint8_t tag[kTagBytes];
  Tag(channel, data, n, trailer, tag);
  if (sodium_memcmp(tag, trailer + kHeaderBytes, kTagBytes) != 0) return Verdict::kBadTag;
  const uint64_t sender = GetBigEndian(trailer + 4);
  const auto stamp = static_cast<int64_t>(GetBigEndian(trailer + 12));
  if (stamp < not_before_us_ || stamp < now_us - kClockWindowUs || stamp > now_us + kClockWindowUs)
    return Verdict::kStale;
  auto it = newest_.find(sender);
  if (it != newest_.end() && stamp <= it->second) return Verdict::kReplayed;
  if (it == newest_.end()) {
    if (newest_.size() >= kMaxSenders) {
      // Only keyed senders get here; forget the quietest, whose next message the clock window
      // still bounds.
      newest_.erase(
          std::min_element(newest_.begin(), newest_.end(),
                           [](const auto& a, const auto& b) { return a.second < b.second; }));
    }
    it = newest_.emplace(sender, stamp).first;
  }
  it->second = stamp;
  *payload_size = n;
  return Verdict::kAuthentic;
}

bool LooksSigned(const uint8_t* data, std::size_t size) {
  return data != nullptr && size >= kSignatureBytes &&
         std::memcmp(data + size - kSignatureBytes, kMagic, 4) == 0;
}

const char* MessageSigner::Describe(Verdict v) {
  switch (v) {
    case Verdict::kAuthentic:
      return "authentic";
    case Verdict::kUnsigned:
      return "unsigned (no signature: a keyless or foreign sender, or a forged packet)";
    case Verdict::kBadTag:
      return "mis-signed (another key, or bytes altered on the way)";
    case Verdict::kReplayed:
      return "replayed (not newer than its sender's newest message)";
    case Verdict::kStale:
      return "stale (stamped before this process started, or more than 30 s from its clock: a "
             "replayed log or capture, or a sender whose clock is behind this board's — check "
             "that the boards' clocks agree, e.g. NTP)";
  }
  return "?";
}

}  // namespace odonata::bus

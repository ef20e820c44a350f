#pragma once
// Signed messages (docs/lcm.md §15), the way MAVLink 2 signs a link: with a key shared by the
// services of one system, every message a service publishes carries a trailer after its LCM
// payload — a sender id, a timestamp that grows with every message of that sender, and an
// HMAC-SHA256 tag over the channel name, the payload and those two fields. LCM's decoders (C++,
// Java: lcm-spy) read the payload and ignore the bytes after it, so lcm-spy, lcm-logger and
// lcm-logplayer handle signed messages as before. A receiver with the key takes a message only
// when its tag is right and its timestamp is newer than the newest of that sender (and not far
// from the receiver's clock); anything else is refused and counted, never acted on. The tag is
// libsodium's keyed BLAKE2b-256 (crypto_generichash with the key: a MAC by design, with no length
// extension to guard against), keyed once per process and copied per message: 0.3-0.8 µs for
// the loop's messages where libsodium 1.0.18's HMAC-SHA-256 took 0.7-1.5 µs (bench_signing).

#include <sodium.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <unordered_map>
#include <vector>

namespace odonata::bus {

/// Bytes a signature adds after the payload: magic (4), sender id (8), timestamp (8), tag (32).
inline constexpr std::size_t kSignatureBytes = 52;

/// The shared key: 32 bytes, written as 64 hex digits in a file only its owner may read.
struct BusKey {
  std::array<unsigned char, 32> bytes{};
};

/// Reads a key file. @throws std::runtime_error naming the file: missing, readable by group or
/// others (a key others can read protects nothing), or not 64 hex digits.
BusKey LoadBusKey(const std::string& path);
/// A new random key as 64 hex digits (odonata-run writes one per run).
std::string NewBusKeyHex();

class MessageSigner {
 public:
  enum class Verdict {
    kAuthentic,  ///< the tag is right and the message is new: `payload_size` bytes are the message
    kUnsigned,   ///< no signature trailer (a keyless sender, a foreign or forged packet)
    kBadTag,     ///< a trailer whose tag is wrong: another key, or altered bytes
    kReplayed,   ///< authentic but not newer than its sender's newest: a resent or replayed copy
    kStale,      ///< authentic but stamped before this receiver started, or far from its clock:
                 ///< a replayed log, or traffic captured before a restart
  };
  /// How far a timestamp may lie from the receiver's clock: two boards' clocks may disagree by a
  /// few seconds; a replayed log is older than this.
  static constexpr int64_t kClockWindowUs = 30'000'000;
  // Nothing stamped before the receiver started is taken, with no allowance for clock skew: a
  // message sent before a process existed cannot be meant for it, and any allowance is a window
  // in which traffic captured just before a restart (odonata-run restarts a dead identifier at
  // once) is taken by the new process as news from a sender it never heard. A board whose clock
  // lags the receiver's by d costs that sender's first d seconds after the receiver starts
  // (counted as stale), nothing more. docs/lcm.md §15.
  /// Senders whose newest timestamp is remembered; only authentic messages add one.
  static constexpr std::size_t kMaxSenders = 4096;

  /// `sender_id` names this process's messages (random per process in services; fixed in tests);
  /// messages stamped before `started_us` are stale (0: no such bound).
  MessageSigner(const BusKey& key, uint64_t sender_id, int64_t started_us = 0);

  /// Appends the signature of `payload` (the LCM-encoded message) on `channel`, stamped `now_us`
  /// or later (timestamps strictly increase per sender).
  void Sign(const std::string& channel, std::vector<uint8_t>* payload, int64_t now_us);

  /// Judges `size` received bytes on `channel` at `now_us`; on kAuthentic `*payload_size` is the
  /// LCM payload's length and the sender's newest timestamp moves to this message's.
  Verdict Verify(const std::string& channel, const uint8_t* data, std::size_t size, int64_t now_us,
                 std::size_t* payload_size);

  static const char* Describe(Verdict v);
  uint64_t sender_id() const { return sender_id_; }

 private:
  void Tag(const std::string& channel, const uint8_t* payload, std::size_t payload_size,
           const uint8_t* header, uint8_t* tag) const;

  crypto_generichash_state keyed_{};  // HMAC state after the key: copied for each message
  uint64_t sender_id_;
  int64_t not_before_us_;
  int64_t last_stamp_ = 0;
  std::unordered_map<uint64_t, int64_t> newest_;  // sender id → newest authentic timestamp
};

/// Whether `size` bytes end in a signature trailer (its magic; not whether it is right): what a
/// process without the key sees on a signed bus.
bool LooksSigned(const uint8_t* data, std::size_t size);

/// A random sender id for this process (libsodium's generator).
uint64_t RandomSenderId();

}  // namespace odonata::bus

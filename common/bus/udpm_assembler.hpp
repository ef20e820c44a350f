#pragma once
// LCM's udpm datagrams (LC02: one whole message; LC03: one fragment of a larger one) turned back
// into messages, with nothing trusted: the wire format and every check are in docs/lcm.md §9.
// Transport-free, so it is tested and fuzzed without a socket.

#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

namespace odonata::bus {

class UdpmAssembler {
 public:
  static constexpr uint32_t kMagicShort = 0x4c433032;   // "LC02"
  static constexpr uint32_t kMagicLong = 0x4c433033;    // "LC03"
  static constexpr std::size_t kMaxChannelLength = 63;  // LCM_MAX_CHANNEL_NAME_LENGTH
  /// The largest fragmented message accepted, and the memory all partial messages may hold.
  static constexpr uint32_t kMaxMessageBytes = 16u << 20;
  static constexpr std::size_t kMaxHeldBytes = 32u << 20;

  enum class Verdict {
    kMessage,     ///< a whole message: channel, data and size are set
    kHeld,        ///< a fragment kept until its message is complete
    kMalformed,   ///< not a valid LCM datagram: problem says why
    kIncomplete,  ///< a fragment or a partial message dropped (its other fragments were lost)
  };
  struct Result {
    Verdict verdict = Verdict::kMalformed;
    std::string_view channel;
    const uint8_t* data = nullptr;  ///< valid until the next Feed
    uint32_t size = 0;
    std::string problem;
  };

  /// One datagram from `sender` (any stable key of its source address and port).
  Result Feed(uint64_t sender, const uint8_t* packet, std::size_t size);

  std::size_t held_bytes() const { return held_bytes_; }

 private:
  struct Partial {
    uint32_t msg_seqno = 0;
    uint32_t size = 0;
    uint16_t fragments = 0;
    uint16_t received = 0;
    uint64_t age = 0;
    std::string channel;
    std::vector<uint8_t> data;
    std::vector<bool> have;
  };
  Result Fragment(uint64_t sender, const uint8_t* packet, std::size_t size);
  void Drop(std::map<uint64_t, Partial>::iterator it);

  std::map<uint64_t, Partial> partial_;  // one message in flight per sender, as LCM keeps
  std::size_t held_bytes_ = 0;
  uint64_t clock_ = 0;
  std::vector<uint8_t> complete_;  // the last reassembled message, handed out by pointer
  std::string channel_;            // and its channel
};

}  // namespace odonata::bus

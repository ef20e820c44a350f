#include "bus/udpm_assembler.hpp"

#include <algorithm>
#include <cstring>

namespace odonata::bus {
namespace {

uint32_t Be32(const uint8_t* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | p[3];
}
uint16_t Be16(const uint8_t* p) { return static_cast<uint16_t>((p[0] << 8) | p[1]); }

UdpmAssembler::Result Malformed(std::string why) {
  UdpmAssembler::Result r;
  r.verdict = UdpmAssembler::Verdict::kMalformed;
  r.problem = std::move(why);
  return r;
}

// The NUL-terminated channel name at the start of `p`, or empty when it has no NUL within
// `size` bytes, is empty or is longer than LCM allows.
std::string_view Channel(const uint8_t* p, std::size_t size) {
  const auto* end = static_cast<const uint8_t*>(std::memchr(p, 0, size));
  if (end == nullptr || end == p) return {};
  const auto length = static_cast<std::size_t>(end - p);
  if (length > UdpmAssembler::kMaxChannelLength) return {};
  return {reinterpret_cast<const char*>(p), length};
}

constexpr std::size_t kShortHeader = 8;  // magic, msg_seqno
constexpr std::size_t kLongHeader = 20;  // + msg_size, fragment_offset, fragment_no, fragments

}  // namespace

UdpmAssembler::Result UdpmAssembler::Feed(uint64_t sender, const uint8_t* packet,
                                          std::size_t size) {
  if (size < kShortHeader) return Malformed(std::to_string(size) + "-byte datagram");
  const uint32_t magic = Be32(packet);
  if (magic == kMagicLong) return Fragment(sender, packet, size);
  if (magic != kMagicShort) return Malformed("datagram without LCM's magic number");
  const std::string_view channel = Channel(packet + kShortHeader, size - kShortHeader);
  if (channel.empty()) return Malformed("LC02 datagram without a valid NUL-terminated channel");
  Result r;
  r.verdict = Verdict::kMessage;
  r.channel = channel;
  const std::size_t offset = kShortHeader + channel.size() + 1;
  r.data = packet + offset;
  r.size = static_cast<uint32_t>(size - offset);
  return r;
}

UdpmAssembler::Result UdpmAssembler::Fragment(uint64_t sender, const uint8_t* packet,
                                              std::size_t size) {
  if (size < kLongHeader) return Malformed(std::to_string(size) + "-byte LC03 datagram");
  const uint32_t seqno = Be32(packet + 4);
  const uint32_t msg_size = Be32(packet + 8);
  const uint32_t offset = Be32(packet + 12);
  const uint16_t number = Be16(packet + 16);
  const uint16_t fragments = Be16(packet + 18);
  if (fragments == 0 || number >= fragments)
    return Malformed("LC03 fragment " + std::to_string(number) + " of " +
                     std::to_string(fragments));
  if (msg_size > kMaxMessageBytes)
    return Malformed("LC03 message of " + std::to_string(msg_size) + " bytes (limit " +
                     std::to_string(kMaxMessageBytes) + ")");
  const uint8_t* payload = packet + kLongHeader;
  std::size_t length = size - kLongHeader;

  auto it = partial_.find(sender);
  Result dropped;  // a partial message this fragment makes hopeless
  if (it != partial_.end() && (it->second.msg_seqno != seqno || it->second.size != msg_size ||
                               it->second.fragments != fragments)) {
    dropped.verdict = Verdict::kIncomplete;
    dropped.problem = "message on '" + it->second.channel + "' missing " +
                      std::to_string(it->second.fragments - it->second.received) + " of " +
                      std::to_string(it->second.fragments) + " fragments";
    Drop(it);
    it = partial_.end();
  }
  if (it == partial_.end()) {
    if (number != 0) {
      // Its first fragment was lost (or sent before this process joined).
      if (dropped.verdict == Verdict::kIncomplete) return dropped;
      Result r;
      r.verdict = Verdict::kIncomplete;
      r.problem = "fragment " + std::to_string(number) + " of a message whose first was lost";
      return r;
    }
    const std::string_view channel = Channel(payload, length);
    if (channel.empty()) return Malformed("LC03 first fragment without a valid channel");
    payload += channel.size() + 1;
    length -= channel.size() + 1;
    // Room for it: the oldest partial messages go first (their senders have moved on or died).
    while (!partial_.empty() && held_bytes_ + msg_size > kMaxHeldBytes) {
      Drop(std::min_element(partial_.begin(), partial_.end(), [](const auto& a, const auto& b) {
        return a.second.age < b.second.age;
      }));
    }
    Partial p;
    p.msg_seqno = seqno;
    p.size = msg_size;
    p.fragments = fragments;
    p.age = clock_++;
    p.channel = std::string(channel);
    p.data.assign(msg_size, 0);
    p.have.assign(fragments, false);
    held_bytes_ += msg_size;
    it = partial_.emplace(sender, std::move(p)).first;
  }
  Partial& p = it->second;
  if (offset > p.size || length > p.size - offset) {
    Drop(it);
    return Malformed("LC03 fragment at " + std::to_string(offset) + " + " + std::to_string(length) +
                     " beyond its " + std::to_string(msg_size) + "-byte message");
  }
  if (!p.have[number]) {  // a repeated fragment is ignored
    std::copy(payload, payload + length, p.data.begin() + offset);
    p.have[number] = true;
    ++p.received;
  }
  if (p.received < p.fragments) {
    if (dropped.verdict == Verdict::kIncomplete) return dropped;
    Result r;
    r.verdict = Verdict::kHeld;
    return r;
  }
  // Whole. (Were a partial dropped above, this is a one-fragment LC03 message, which LCM never
  // sends: the drop goes unreported then.)
  complete_ = std::move(p.data);
  Result r;
  r.verdict = Verdict::kMessage;
  r.size = p.size;
  channel_ = std::move(p.channel);
  Drop(it);
  r.channel = channel_;
  r.data = complete_.data();
  return r;
}

void UdpmAssembler::Drop(std::map<uint64_t, Partial>::iterator it) {
  held_bytes_ -= it->second.size;
  partial_.erase(it);
}

}  // namespace odonata::bus

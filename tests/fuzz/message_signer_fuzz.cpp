// Fuzz harness: a keyed receiver's verdict on any bytes (docs/lcm.md §15). The first byte picks a
// channel; the rest is a received message. Nothing may crash or read past the bytes, and nothing
// forged passes: random bytes are never authentic, the same bytes signed with the key are, once,
// and one flipped bit anywhere in them (payload or signature) makes them not authentic again.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "bus/bus_node.hpp"
#include "bus/message_signer.hpp"

namespace {

odonata::bus::BusKey FixedKey() {
  odonata::bus::BusKey k;
  for (std::size_t i = 0; i < k.bytes.size(); ++i) k.bytes[i] = static_cast<unsigned char>(3 * i);
  return k;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  using odonata::bus::MessageSigner;
  static const std::vector<std::string> kChannels = {"DIMAV_STATE", "DIMAV_COMMAND", "ODONATA_ACK",
                                                     "ODONATA_CONTROL", "X"};
  if (size == 0) return 0;
  const std::string& channel = kChannels[data[0] % kChannels.size()];
  const std::vector<uint8_t> bytes(data + 1, data + size);
  const int64_t now = odonata::bus::NowUtime();
  MessageSigner sender(FixedKey(), 1), receiver(FixedKey(), 2);
  std::size_t n = 0;
  if (receiver.Verify(channel, bytes.data(), bytes.size(), now, &n) ==
      MessageSigner::Verdict::kAuthentic)
    std::abort();  // a forged tag passed
  std::vector<uint8_t> signed_bytes = bytes;
  sender.Sign(channel, &signed_bytes, now);
  if (receiver.Verify(channel, signed_bytes.data(), signed_bytes.size(), now, &n) !=
          MessageSigner::Verdict::kAuthentic ||
      n != bytes.size())
    std::abort();  // a genuine message refused
  if (receiver.Verify(channel, signed_bytes.data(), signed_bytes.size(), now, &n) ==
      MessageSigner::Verdict::kAuthentic)
    std::abort();  // a replay taken
  const std::size_t bit = (static_cast<std::size_t>(data[0]) * 131) % (8 * signed_bytes.size());
  signed_bytes[bit / 8] ^= static_cast<uint8_t>(1u << (bit % 8));
  MessageSigner fresh(FixedKey(), 3);
  if (fresh.Verify(channel, signed_bytes.data(), signed_bytes.size(), now, &n) ==
      MessageSigner::Verdict::kAuthentic)
    std::abort();  // an altered message passed
  return 0;
}

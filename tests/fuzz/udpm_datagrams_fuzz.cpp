// Fuzz harness: UdpmAssembler, which every service runs on every datagram of its multicast group
// before anything is decoded. The input is a sequence of datagrams, each as one byte of sender
// (four senders, so partial messages interleave), two bytes of length and the bytes themselves.
// Nothing may crash, and the promises the callers rely on must hold for any input.
#include <cstddef>
#include <cstdint>
#include <cstdlib>

#include "bus/udpm_assembler.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using odonata::bus::UdpmAssembler;
  UdpmAssembler assembler;
  std::size_t at = 0;
  while (at + 3 <= size) {
    const uint64_t sender = data[at] % 4;
    std::size_t length = (std::size_t{data[at + 1]} << 8) | data[at + 2];
    at += 3;
    length = length < size - at ? length : size - at;
    const auto r = assembler.Feed(sender, data + at, length);
    at += length;
    if (assembler.held_bytes() > UdpmAssembler::kMaxHeldBytes) std::abort();
    if (r.verdict == UdpmAssembler::Verdict::kMessage) {
      if (r.channel.empty() || r.channel.size() > UdpmAssembler::kMaxChannelLength) std::abort();
      if (r.size > 0 && r.data == nullptr) std::abort();
      // Every byte of the message must be readable (ASan checks the read).
      volatile uint8_t sum = 0;
      for (uint32_t i = 0; i < r.size; ++i) sum = static_cast<uint8_t>(sum + r.data[i]);
    }
  }
  return 0;
}

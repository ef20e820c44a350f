#include "bus/udpm_channel_filter.hpp"

#include <algorithm>
#include <cstdint>

#include "bus/udpm_assembler.hpp"

namespace odonata::bus {
namespace {

// A UDP socket's filter sees the datagram from its UDP header (8 bytes); LC02's own header
// (magic, seqno) is 8 more, then the NUL-terminated channel name.
constexpr uint32_t kMagicAt = 8;
constexpr uint32_t kChannelAt = 16;
constexpr uint32_t kAccept = 0xffffffff;  // keep the whole datagram
constexpr std::size_t kMaxInstructions = 1024;

sock_filter Statement(uint16_t code, uint32_t k) { return sock_filter{code, 0, 0, k}; }

}  // namespace

bool IsLiteralChannel(const std::string& subscription) {
  return !subscription.empty() && subscription.size() <= UdpmAssembler::kMaxChannelLength &&
         std::all_of(subscription.begin(), subscription.end(), [](char c) {
           return (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') ||
                  c == '_' || c == '-' || c == '/' || c == ':' || c == '#' || c == '@';
         });
}

std::optional<std::vector<sock_filter>> ChannelFilterProgram(std::vector<std::string> channels,
                                                             bool fragments) {
  std::sort(channels.begin(), channels.end());
  channels.erase(std::unique(channels.begin(), channels.end()), channels.end());
  // Shortest first: a load past a datagram's end ends the program with "drop", and a datagram
  // long enough for a longer name is long enough for every shorter one checked before it.
  std::stable_sort(channels.begin(), channels.end(),
                   [](const std::string& a, const std::string& b) { return a.size() < b.size(); });

  // One block per channel: compare the name and its NUL in 4-, 2- and 1-byte loads; any mismatch
  // jumps to the next block, the end of a block accepts.
  std::vector<std::vector<sock_filter>> blocks;
  for (const std::string& name : channels) {
    if (!IsLiteralChannel(name)) return std::nullopt;
    std::string bytes = name;
    bytes.push_back('\0');
    std::vector<sock_filter> block;
    std::size_t at = 0;
    while (at < bytes.size()) {
      const std::size_t width = bytes.size() - at >= 4 ? 4 : bytes.size() - at >= 2 ? 2 : 1;
      uint32_t value = 0;
      for (std::size_t i = 0; i < width; ++i)
        value = (value << 8) | static_cast<unsigned char>(bytes[at + i]);
      const uint16_t size = width == 4 ? BPF_W : width == 2 ? BPF_H : BPF_B;
      block.push_back(Statement(BPF_LD | size | BPF_ABS, kChannelAt + static_cast<uint32_t>(at)));
      block.push_back(sock_filter{BPF_JMP | BPF_JEQ | BPF_K, 0, 0, value});  // jf set below
      at += width;
    }
    block.push_back(Statement(BPF_RET | BPF_K, kAccept));
    blocks.push_back(std::move(block));
  }

  std::vector<sock_filter> program;
  // Too short for LCM's header: user space counts it (a load past the end would drop it here).
  program.push_back(Statement(BPF_LD | BPF_W | BPF_LEN, 0));
  program.push_back(sock_filter{BPF_JMP | BPF_JGE | BPF_K, 1, 0, kChannelAt});
  program.push_back(Statement(BPF_RET | BPF_K, kAccept));
  program.push_back(Statement(BPF_LD | BPF_W | BPF_ABS, kMagicAt));
  program.push_back(sock_filter{BPF_JMP | BPF_JEQ | BPF_K, 3, 0, UdpmAssembler::kMagicShort});
  // LC03: a fragment, kept only when some subscription may take a fragmented message.
  program.push_back(sock_filter{BPF_JMP | BPF_JEQ | BPF_K, 0, 1, UdpmAssembler::kMagicLong});
  program.push_back(Statement(BPF_RET | BPF_K, fragments ? kAccept : 0));
  program.push_back(Statement(BPF_RET | BPF_K, kAccept));  // not LCM: user space counts it
  for (auto& block : blocks) {
    const std::size_t next = block.size();  // index of the next block, relative to this one
    for (std::size_t i = 0; i < block.size(); ++i) {
      if (BPF_CLASS(block[i].code) != BPF_JMP) continue;
      const std::size_t jump = next - i - 1;
      if (jump > 255) return std::nullopt;
      block[i].jf = static_cast<uint8_t>(jump);
    }
    program.insert(program.end(), block.begin(), block.end());
  }
  program.push_back(Statement(BPF_RET | BPF_K, 0));
  if (program.size() > kMaxInstructions) return std::nullopt;
  return program;
}

}  // namespace odonata::bus

// The kernel runs the channel filter: LC02 datagrams on other channels never reach the socket,
// while the subscribed channels, fragments and non-LCM datagrams (counted in user space) do.
// Over loopback unicast, so nothing leaves the host and no multicast route is needed.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bus/udpm_assembler.hpp"
#include "bus/udpm_channel_filter.hpp"

namespace odonata::bus {
namespace {

struct Fd {
  int fd;
  explicit Fd(int f) : fd(f) {}
  ~Fd() { close(fd); }
};

std::vector<uint8_t> Datagram(uint32_t magic, const std::string& channel, std::size_t payload) {
  std::vector<uint8_t> b;
  b.reserve(8 + channel.size() + 1 + payload);
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<uint8_t>(magic >> s));
  for (uint8_t v : {0, 0, 0, 1}) b.push_back(v);
  for (char c : channel) b.push_back(static_cast<uint8_t>(c));
  b.push_back(0);
  b.resize(b.size() + payload, 0x55);
  return b;
}

// Sends each datagram to a socket filtered for `channels` and returns the ones that arrived.
std::vector<std::string> Passed(
    const std::vector<std::string>& channels,
    const std::vector<std::pair<std::string, std::vector<uint8_t>>>& sent, bool fragments = true) {
  Fd rx(socket(AF_INET, SOCK_DGRAM, 0)), tx(socket(AF_INET, SOCK_DGRAM, 0));
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  EXPECT_EQ(bind(rx.fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr), 0);
  socklen_t len = sizeof addr;
  getsockname(rx.fd, reinterpret_cast<sockaddr*>(&addr), &len);
  const auto program = ChannelFilterProgram(channels, fragments);
  EXPECT_TRUE(program.has_value());
  if (!program) return {};
  sock_fprog fprog{static_cast<unsigned short>(program->size()),
                   const_cast<sock_filter*>(program->data())};
  EXPECT_EQ(setsockopt(rx.fd, SOL_SOCKET, SO_ATTACH_FILTER, &fprog, sizeof fprog), 0);
  for (const auto& [name, bytes] : sent)
    EXPECT_EQ(sendto(tx.fd, bytes.data(), bytes.size(), 0, reinterpret_cast<sockaddr*>(&addr),
                     sizeof addr),
              static_cast<ssize_t>(bytes.size()));
  // A marker the filter passes, sent last: once it is read, everything before it was decided.
  const auto marker = Datagram(0x12345678, "", 0);
  sendto(tx.fd, marker.data(), marker.size(), 0, reinterpret_cast<sockaddr*>(&addr), sizeof addr);
  std::vector<std::string> got;
  std::vector<uint8_t> buf(70000);
  for (;;) {
    pollfd p{rx.fd, POLLIN, 0};
    if (poll(&p, 1, 5000) != 1) {
      ADD_FAILURE() << "the marker never arrived";
      break;
    }
    const ssize_t n = recv(rx.fd, buf.data(), buf.size(), 0);
    if (n >= 4 && buf[0] == 0x12 && buf[1] == 0x34) break;
    for (const auto& [name, bytes] : sent)
      if (static_cast<std::size_t>(n) == bytes.size() &&
          std::equal(bytes.begin(), bytes.end(), buf.begin()))
        got.push_back(name);
  }
  return got;
}

TEST(UdpmChannelFilter, TheKernelDropsOtherChannelsOnly) {
  const uint32_t lc02 = UdpmAssembler::kMagicShort, lc03 = UdpmAssembler::kMagicLong;
  const std::vector<std::pair<std::string, std::vector<uint8_t>>> sent{
      {"command", Datagram(lc02, "DIMAV_COMMAND", 200)},
      {"state", Datagram(lc02, "DIMAV_STATE", 300)},      // not subscribed
      {"prefix", Datagram(lc02, "DIMAV_COMMANDS", 200)},  // longer name, same start
      {"shorter", Datagram(lc02, "DIMAV_COMMAN", 200)},   // shorter name
      {"control", Datagram(lc02, "ODONATA_CONTROL", 0)},  // empty payload
      {"c", Datagram(lc02, "C", 0)},                      // one letter, nothing after it
      {"fragment", Datagram(lc03, "DIMAV_STATE", 100)},   // reassembled in user space
      {"garbage", std::vector<uint8_t>{1, 2, 3}},         // counted in user space
      {"no-nul", std::vector<uint8_t>{0x4c, 0x43, 0x30, 0x32, 0, 0, 0, 1, 'C'}},
  };
  const auto got = Passed({"ODONATA_CONTROL", "DIMAV_COMMAND", "C"}, sent);
  EXPECT_EQ(got, (std::vector<std::string>{"command", "control", "c", "fragment", "garbage"}));
}

// A node none of whose subscriptions takes a fragmented message (no snapshot, no signals): the
// kernel drops every fragment, whatever its channel, so a flood of large messages never fills
// its receive buffer; everything else is judged as before.
TEST(UdpmChannelFilter, WithoutFragmentedSubscriptionsEveryFragmentIsDropped) {
  const uint32_t lc02 = UdpmAssembler::kMagicShort, lc03 = UdpmAssembler::kMagicLong;
  const std::vector<std::pair<std::string, std::vector<uint8_t>>> sent{
      {"command", Datagram(lc02, "DIMAV_COMMAND", 200)},
      {"state", Datagram(lc02, "DIMAV_STATE", 300)},
      {"snapshot", Datagram(lc03, "ODONATA_MODEL", 60000)},
      {"subscribed-fragment", Datagram(lc03, "DIMAV_COMMAND", 100)},
      {"garbage", std::vector<uint8_t>{1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14}},
  };
  EXPECT_EQ(Passed({"DIMAV_COMMAND"}, sent, false),
            (std::vector<std::string>{"command", "garbage"}));
  EXPECT_EQ(Passed({"DIMAV_COMMAND"}, sent, true),
            (std::vector<std::string>{"command", "snapshot", "subscribed-fragment", "garbage"}));
}

TEST(UdpmChannelFilter, OnlyLiteralNamesAreFiltered) {
  EXPECT_TRUE(IsLiteralChannel("DIMAV_STATE_v2"));
  EXPECT_FALSE(IsLiteralChannel(".*"));
  EXPECT_FALSE(IsLiteralChannel("DIMAV_.*"));
  EXPECT_FALSE(IsLiteralChannel(""));
  EXPECT_FALSE(ChannelFilterProgram({"DIMAV_STATE", "A|B"}).has_value());
  EXPECT_TRUE(ChannelFilterProgram({}).has_value());  // subscribed to nothing: drop every LC02
}

}  // namespace
}  // namespace odonata::bus

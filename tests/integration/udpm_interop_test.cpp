// odonata's own udpm receiver and sender against LCM 1.3.1's, over real multicast: run by ctest
// inside a private network namespace (see CMakeLists.txt), so nothing leaves the host. Messages
// of every size LCM sends whole or in fragments arrive byte for byte in both directions, and the
// kernel filter keeps other channels away from a node that did not subscribe to them.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

#include "bus/bus_node.hpp"
#include "odonata/ack_t.hpp"

namespace odonata::bus {
namespace {

const char* kUrl = "udpm://239.255.76.67:7693?ttl=0";

std::vector<uint8_t> Payload(std::size_t n, int salt) {
  std::vector<uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(i * 13 + salt);
  return v;
}

BusOptions Options(const std::string& service) {
  BusOptions o;
  o.lcm_url = kUrl;
  o.service = service;
  o.heartbeat_period_s = 0;
  return o;
}

// Runs the node's loop until `done` or 5 s.
template <class Done>
void RunUntil(BusNode& node, Done done) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (!done() && std::chrono::steady_clock::now() < end) {
    node.io().restart();
    node.io().run_for(std::chrono::milliseconds(5));
  }
}

TEST(UdpmInterop, LcmsMessagesOfEverySizeReachTheOwnReceiver) {
  BusNode node(Options("receiver"));
  ASSERT_TRUE(node.own_receiver());
  std::vector<std::vector<uint8_t>> got;
  node.SubscribeRaw("BIG", [&](const lcm::ReceiveBuffer& rbuf, const std::string&) {
    const auto* p = static_cast<const uint8_t*>(rbuf.data);
    got.emplace_back(p, p + rbuf.data_size);
  });
  node.SubscribeRaw("OTHER", [&](const lcm::ReceiveBuffer&, const std::string&) {});
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  // Whole (LC02) up to LCM's limit, then fragments (LC03). Larger bursts than the kernel's
  // default receive buffer (208 kB) are lost to both receivers alike: raise it with recv_buf_size.
  const std::vector<std::size_t> sizes{0, 1, 1000, 65495, 65496, 100000, 150000};
  for (std::size_t i = 0; i < sizes.size(); ++i) {
    const auto p = Payload(sizes[i], static_cast<int>(i));
    ASSERT_EQ(lcm.publish("BIG", p.data(), static_cast<unsigned>(p.size())), 0);
    RunUntil(node, [&] { return got.size() == i + 1; });
    ASSERT_EQ(got.size(), i + 1) << "message of " << sizes[i] << " bytes never arrived";
    EXPECT_EQ(got[i], p) << "message of " << sizes[i] << " bytes";
  }
  EXPECT_EQ(node.stats().decode_errors, 0);
  EXPECT_EQ(node.stats().dropped, 0);
}

TEST(UdpmInterop, TheOwnSenderIsReadByLcmAndTogetherKeepsOrder) {
  BusNode node(Options("sender"));
  ASSERT_TRUE(node.own_receiver());
  lcm::LCM lcm(kUrl);
  struct Sink {
    std::vector<std::string> channels;
    std::vector<int64_t> seqs;
  } sink;
  // LCM's C API with a plain callback: in the sanitizer build, UBSan rejects the vptr of the C++
  // API's LCMMHUntypedSubscription<Sink> when the callback runs (lcm-cpp-impl.hpp:108, "invalid
  // vptr"), although the subscription pointer LCM passes back is the right one; the C API has no
  // polymorphic wrapper to check. One subscription per channel; one socket keeps their order.
  const lcm_msg_handler_t on = [](const lcm_recv_buf_t* rbuf, const char* channel, void* user) {
    auto* s = static_cast<Sink*>(user);
    odonata::ack_t a;
    if (a.decode(rbuf->data, 0, static_cast<int>(rbuf->data_size)) > 0)
      s->seqs.push_back(a.state_seq);
    s->channels.emplace_back(channel);
  };
  for (const char* channel : {"ACK_ONE", "ACK_TWO", "ACK_THREE"})
    ASSERT_NE(lcm_subscribe(lcm.getUnderlyingLCM(), channel, on, &sink), nullptr);
  odonata::ack_t a{};
  a.service = "sender";
  a.instance = "sender";
  a.state_seq = 1;
  ASSERT_TRUE(node.Publish("ACK_ONE", a));
  odonata::ack_t b = a;
  b.state_seq = 2;
  a.state_seq = 3;
  ASSERT_TRUE(node.PublishTogether("ACK_TWO", b, "ACK_THREE", a));
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  while (sink.channels.size() < 3 && std::chrono::steady_clock::now() < end) lcm.handleTimeout(50);
  EXPECT_EQ(sink.channels, (std::vector<std::string>{"ACK_ONE", "ACK_TWO", "ACK_THREE"}));
  EXPECT_EQ(sink.seqs, (std::vector<int64_t>{1, 2, 3}));
  EXPECT_EQ(node.stats().messages_out, 3);
}

TEST(UdpmInterop, ANodeHearsOnlyItsOwnChannelsAndCountsGarbage) {
  BusNode node(Options("filtered"));
  int mine = 0;
  node.Subscribe<odonata::ack_t>("MINE", [&](const odonata::ack_t&) { ++mine; });
  lcm::LCM lcm(kUrl);
  odonata::ack_t a{};
  for (int i = 0; i < 50; ++i) lcm.publish("NOT_MINE", &a);
  lcm.publish("MINE", &a);
  RunUntil(node, [&] { return mine == 1; });
  EXPECT_EQ(mine, 1);
  // The 50 others were dropped by the kernel, never read: only MINE counts as a message in.
  EXPECT_EQ(node.stats().messages_in, 1);
  // Garbage is not LCM's format: it passes the filter and is counted, not delivered.
  const std::vector<uint8_t> junk{1, 2, 3};
  BusNode raw_sender(Options("junk"));
  lcm.publish("MINE", junk.data(), static_cast<unsigned>(junk.size()));  // undecodable ack_t
  RunUntil(node, [&] { return node.stats().decode_errors == 1; });
  EXPECT_EQ(node.stats().decode_errors, 1);
}

// A node whose receive buffer overflows while it is not reading learns how many datagrams the
// kernel dropped (SO_RXQ_OVFL) from the next one it reads: its own loss is counted as dropped
// and said, not silent (issue 51 point 5: a logger's own loss).
TEST(UdpmInterop, DatagramsTheKernelDroppedForAFullBufferAreCounted) {
  BusOptions o = Options("small-buffer");
  o.lcm_url = std::string(kUrl) + "&recv_buf_size=4096";
  BusNode node(o);
  ASSERT_TRUE(node.own_receiver());
  int64_t got = 0;
  // A recorder's subscription (a regex): no channel filter, whose drops the kernel counts alike.
  node.SubscribeRaw("FLOO.*", [&](const lcm::ReceiveBuffer&, const std::string&) { ++got; });
  lcm::LCM lcm(kUrl);
  ASSERT_TRUE(lcm.good());
  const auto p = Payload(1000, 3);
  const int sent = 400;  // far more than 4 kB (8 kB of truesize) hold: the node is not reading
  for (int i = 0; i < sent; ++i)
    ASSERT_EQ(lcm.publish("FLOOD", p.data(), static_cast<unsigned>(p.size())), 0);
  // What the buffer held, queued before any drop; the next datagram carries the drops' count.
  RunUntil(node, [&] { return got > 0; });
  node.io().restart();
  node.io().run_for(std::chrono::milliseconds(20));
  ASSERT_LT(got, sent);
  lcm.publish("FLOOD", p.data(), static_cast<unsigned>(p.size()));
  RunUntil(node, [&] { return got + node.kernel_dropped() >= sent + 1; });
  EXPECT_EQ(got + node.kernel_dropped(), sent + 1);
  EXPECT_EQ(node.stats().dropped, node.kernel_dropped());
  EXPECT_NE(node.stats().last_error.find("receive buffer full"), std::string::npos)
      << node.stats().last_error;
}

}  // namespace
}  // namespace odonata::bus

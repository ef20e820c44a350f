// UdpmAssembler and ParseUdpmEndpoint: LCM's udpm datagrams, whole and in fragments, turned back
// into messages, and every malformed or incomplete datagram named instead of delivered.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "bus/udpm_assembler.hpp"
#include "bus/udpm_endpoint.hpp"

namespace odonata::bus {
namespace {

using Verdict = UdpmAssembler::Verdict;

void Put32(std::vector<uint8_t>& b, uint32_t v) {
  for (int s = 24; s >= 0; s -= 8) b.push_back(static_cast<uint8_t>(v >> s));
}
void Put16(std::vector<uint8_t>& b, uint16_t v) {
  b.push_back(static_cast<uint8_t>(v >> 8));
  b.push_back(static_cast<uint8_t>(v));
}

std::vector<uint8_t> Short(const std::string& channel, const std::vector<uint8_t>& data,
                           bool nul = true) {
  std::vector<uint8_t> b;
  Put32(b, UdpmAssembler::kMagicShort);
  Put32(b, 7);
  b.insert(b.end(), channel.begin(), channel.end());
  if (nul) b.push_back(0);
  b.insert(b.end(), data.begin(), data.end());
  return b;
}

// The fragments LCM's sender makes of `data`: the first carries the channel, every fragment
// at most `chunk` payload bytes.
std::vector<std::vector<uint8_t>> Fragments(const std::string& channel,
                                            const std::vector<uint8_t>& data, uint32_t seqno,
                                            std::size_t chunk) {
  std::vector<std::vector<uint8_t>> out;
  const std::size_t first = chunk - channel.size() - 1;
  std::vector<std::size_t> starts{0};
  for (std::size_t at = first; at < data.size(); at += chunk) starts.push_back(at);
  for (std::size_t i = 0; i < starts.size(); ++i) {
    std::vector<uint8_t> b;
    Put32(b, UdpmAssembler::kMagicLong);
    Put32(b, seqno);
    Put32(b, static_cast<uint32_t>(data.size()));
    Put32(b, static_cast<uint32_t>(starts[i]));
    Put16(b, static_cast<uint16_t>(i));
    Put16(b, static_cast<uint16_t>(starts.size()));
    if (i == 0) {
      b.insert(b.end(), channel.begin(), channel.end());
      b.push_back(0);
    }
    const std::size_t end =
        std::min(data.size(), i + 1 < starts.size() ? starts[i + 1] : data.size());
    b.insert(b.end(), data.begin() + static_cast<long>(starts[i]),
             data.begin() + static_cast<long>(end));
    out.push_back(std::move(b));
  }
  return out;
}

std::vector<uint8_t> Bytes(std::size_t n) {
  std::vector<uint8_t> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = static_cast<uint8_t>(i * 31 + 7);
  return v;
}

std::vector<uint8_t> Data(const UdpmAssembler::Result& r) {
  return std::vector<uint8_t>(r.data, r.data + r.size);
}

TEST(UdpmAssembler, AShortDatagramIsOneMessage) {
  UdpmAssembler a;
  const auto packet = Short("DIMAV_STATE", Bytes(300));
  const auto r = a.Feed(1, packet.data(), packet.size());
  ASSERT_EQ(r.verdict, Verdict::kMessage);
  EXPECT_EQ(r.channel, "DIMAV_STATE");
  EXPECT_EQ(Data(r), Bytes(300));
  const auto empty = Short("X", {});
  const auto e = a.Feed(1, empty.data(), empty.size());
  ASSERT_EQ(e.verdict, Verdict::kMessage);
  EXPECT_EQ(e.size, 0u);
}

TEST(UdpmAssembler, MalformedDatagramsAreNamed) {
  UdpmAssembler a;
  const std::vector<uint8_t> tiny{0x4c, 0x43, 0x30};
  EXPECT_EQ(a.Feed(1, tiny.data(), tiny.size()).verdict, Verdict::kMalformed);
  auto bad_magic = Short("A", Bytes(10));
  bad_magic[3] = 'X';
  EXPECT_EQ(a.Feed(1, bad_magic.data(), bad_magic.size()).verdict, Verdict::kMalformed);
  // The 19-byte datagram LCM 1.3.1 passed on with size -1: a channel name without a NUL.
  const auto no_nul = Short("ODONATA_MOD", {}, false);
  ASSERT_EQ(no_nul.size(), 19u);
  const auto r = a.Feed(1, no_nul.data(), no_nul.size());
  EXPECT_EQ(r.verdict, Verdict::kMalformed);
  EXPECT_NE(r.problem.find("NUL"), std::string::npos) << r.problem;
  const auto empty_name = Short("", Bytes(4));
  EXPECT_EQ(a.Feed(1, empty_name.data(), empty_name.size()).verdict, Verdict::kMalformed);
  const auto long_name = Short(std::string(64, 'C'), Bytes(4));
  EXPECT_EQ(a.Feed(1, long_name.data(), long_name.size()).verdict, Verdict::kMalformed);
}

TEST(UdpmAssembler, FragmentsInAnyOrderMakeTheMessage) {
  const auto data = Bytes(200000);
  auto frags = Fragments("ODONATA_MODEL", data, 42, 65487);
  ASSERT_EQ(frags.size(), 4u);
  UdpmAssembler a;
  // The first fragment must come first (it names the channel); the others in any order.
  std::vector<std::size_t> order{0, 3, 1, 2};
  for (std::size_t k = 0; k < order.size(); ++k) {
    const auto& f = frags[order[k]];
    const auto r = a.Feed(9, f.data(), f.size());
    if (k + 1 < order.size()) {
      EXPECT_EQ(r.verdict, Verdict::kHeld);
    } else {
      ASSERT_EQ(r.verdict, Verdict::kMessage);
      EXPECT_EQ(r.channel, "ODONATA_MODEL");
      EXPECT_EQ(Data(r), data);
    }
  }
  EXPECT_EQ(a.held_bytes(), 0u);
}

TEST(UdpmAssembler, TwoSendersInterleaveAndARepeatedFragmentCountsOnce) {
  const auto d1 = Bytes(3000), d2 = Bytes(2500);
  const auto f1 = Fragments("A", d1, 1, 1000), f2 = Fragments("B", d2, 1, 1000);
  UdpmAssembler a;
  EXPECT_EQ(a.Feed(1, f1[0].data(), f1[0].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(2, f2[0].data(), f2[0].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(1, f1[1].data(), f1[1].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(1, f1[1].data(), f1[1].size()).verdict, Verdict::kHeld);  // repeated
  EXPECT_EQ(a.Feed(2, f2[1].data(), f2[1].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(1, f1[2].data(), f1[2].size()).verdict, Verdict::kHeld);
  const auto r1 = a.Feed(1, f1[3].data(), f1[3].size());
  ASSERT_EQ(r1.verdict, Verdict::kMessage);
  EXPECT_EQ(Data(r1), d1);
  const auto r2 = a.Feed(2, f2[2].data(), f2[2].size());
  ASSERT_EQ(r2.verdict, Verdict::kMessage);
  EXPECT_EQ(r2.channel, "B");
  EXPECT_EQ(Data(r2), d2);
}

TEST(UdpmAssembler, ALostFragmentDropsItsMessageAndTheNextOneStillArrives) {
  const auto d = Bytes(3000);
  const auto first = Fragments("A", d, 1, 1000), second = Fragments("A", d, 2, 1000);
  UdpmAssembler a;
  EXPECT_EQ(a.Feed(1, first[0].data(), first[0].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(1, first[1].data(), first[1].size()).verdict, Verdict::kHeld);
  // first[2] and first[3] are lost; the next message's first fragment gives the first up.
  const auto r = a.Feed(1, second[0].data(), second[0].size());
  EXPECT_EQ(r.verdict, Verdict::kIncomplete);
  EXPECT_NE(r.problem.find("missing 2 of 4"), std::string::npos) << r.problem;
  for (std::size_t i = 1; i + 1 < second.size(); ++i)
    EXPECT_EQ(a.Feed(1, second[i].data(), second[i].size()).verdict, Verdict::kHeld);
  const auto last = a.Feed(1, second.back().data(), second.back().size());
  ASSERT_EQ(last.verdict, Verdict::kMessage);
  EXPECT_EQ(Data(last), d);
  // A fragment whose first was never seen is dropped, not held.
  EXPECT_EQ(a.Feed(5, second[2].data(), second[2].size()).verdict, Verdict::kIncomplete);
  EXPECT_EQ(a.held_bytes(), 0u);
}

TEST(UdpmAssembler, ForgedFragmentHeadersAreRefusedAndMemoryStaysBounded) {
  UdpmAssembler a;
  auto f = Fragments("A", Bytes(3000), 1, 1000);
  auto beyond = f[1];
  beyond[12] = 0x7f;  // fragment offset far past the message
  EXPECT_EQ(a.Feed(1, f[0].data(), f[0].size()).verdict, Verdict::kHeld);
  EXPECT_EQ(a.Feed(1, beyond.data(), beyond.size()).verdict, Verdict::kMalformed);
  auto number = f[0];
  number[17] = 9;  // fragment 9 of 4
  EXPECT_EQ(a.Feed(2, number.data(), number.size()).verdict, Verdict::kMalformed);
  auto huge = f[0];
  huge[8] = 0x7f;  // a 2 GB message
  EXPECT_EQ(a.Feed(3, huge.data(), huge.size()).verdict, Verdict::kMalformed);
  // Many senders each claiming a 16 MB message: the oldest are dropped to stay within the limit.
  const auto big = Fragments("B", Bytes(UdpmAssembler::kMaxMessageBytes), 1, 65487);
  for (uint64_t sender = 10; sender < 20; ++sender) {
    a.Feed(sender, big[0].data(), big[0].size());
    EXPECT_LE(a.held_bytes(), UdpmAssembler::kMaxHeldBytes);
  }
}

TEST(UdpmEndpoint, ReadsTheUrlsLcmReads) {
  const auto e = ParseUdpmEndpoint("udpm://239.255.76.67:7687?ttl=1&recv_buf_size=2097152");
  ASSERT_TRUE(e.has_value());
  EXPECT_EQ(e->group, "239.255.76.67");
  EXPECT_EQ(e->port, 7687);
  EXPECT_EQ(e->recv_buf_size, 2097152);
  EXPECT_EQ(e->ttl, 1);
  const auto d = ParseUdpmEndpoint("udpm://");
  ASSERT_TRUE(d.has_value());
  EXPECT_EQ(d->port, 7667);
  EXPECT_FALSE(ParseUdpmEndpoint("memq://").has_value());
  EXPECT_FALSE(ParseUdpmEndpoint("udpm://239.255.76.67").has_value());  // LCM's own reading
  EXPECT_FALSE(ParseUdpmEndpoint("udpm://somehost:7667").has_value());
  EXPECT_FALSE(ParseUdpmEndpoint("udpm://239.255.76.67:99999").has_value());
  EXPECT_EQ(EffectiveLcmUrl("memq://"), "memq://");
}

}  // namespace
}  // namespace odonata::bus

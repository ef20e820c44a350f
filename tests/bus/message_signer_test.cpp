// Signed messages (docs/lcm.md §15): MessageSigner's verdicts, the key file's checks, and a
// BusNode with a key that acts only on authentic, new messages while LCM's decoders still read
// signed ones.
#include "bus/message_signer.hpp"

#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "odonata/ack_t.hpp"
#include "support/memq_bus.hpp"

namespace odonata::bus {
namespace {

constexpr int64_t kNow = 1'800'000'000'000'000;  // a fixed clock, µs

BusKey KeyOf(unsigned char fill) {
  BusKey k;
  k.bytes.fill(fill);
  return k;
}

std::vector<uint8_t> Payload(const std::string& text) { return {text.begin(), text.end()}; }

MessageSigner::Verdict Check(MessageSigner& receiver, const std::string& channel,
                             const std::vector<uint8_t>& bytes, int64_t now = kNow) {
  std::size_t n = 0;
  const auto v = receiver.Verify(channel, bytes.data(), bytes.size(), now, &n);
  if (v == MessageSigner::Verdict::kAuthentic) {
    EXPECT_EQ(n, bytes.size() - kSignatureBytes);
  }
  return v;
}

TEST(MessageSigner, AcceptsEachAuthenticMessageOnceAndRefusesTheRest) {
  MessageSigner sender(KeyOf(7), 11), receiver(KeyOf(7), 22), stranger(KeyOf(8), 33);
  auto a = Payload("state 1");
  sender.Sign("DIMAV_STATE", &a, kNow);
  ASSERT_EQ(a.size(), 7 + kSignatureBytes);
  auto b = Payload("state 2");
  sender.Sign("DIMAV_STATE", &b, kNow);  // the same clock: the timestamp still grows
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", a), MessageSigner::Verdict::kAuthentic);
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", a), MessageSigner::Verdict::kReplayed);
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", b), MessageSigner::Verdict::kAuthentic);
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", a), MessageSigner::Verdict::kReplayed);  // older

  auto c = Payload("state 3");
  sender.Sign("DIMAV_STATE", &c, kNow);
  EXPECT_EQ(Check(receiver, "DIMAV_COMMAND", c), MessageSigner::Verdict::kBadTag);  // channel
  auto altered = c;
  altered[0] ^= 1;
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", altered), MessageSigner::Verdict::kBadTag);
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", Payload("no signature at all")),
            MessageSigner::Verdict::kUnsigned);
  auto foreign = Payload("state 3");
  stranger.Sign("DIMAV_STATE", &foreign, kNow);
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", foreign), MessageSigner::Verdict::kBadTag);
  // Refusals moved nothing: the genuine message is still new.
  EXPECT_EQ(Check(receiver, "DIMAV_STATE", c), MessageSigner::Verdict::kAuthentic);
}

TEST(MessageSigner, ARecordedMessageIsStaleOnceItLeavesTheClockWindow) {
  MessageSigner recorder(KeyOf(7), 11), receiver(KeyOf(7), 22);
  auto old = Payload("freeze");
  recorder.Sign("ODONATA_CONTROL", &old, kNow);
  const int64_t later = kNow + MessageSigner::kClockWindowUs + 1;
  EXPECT_EQ(Check(receiver, "ODONATA_CONTROL", old, later), MessageSigner::Verdict::kStale);
  EXPECT_EQ(Check(receiver, "ODONATA_CONTROL", old, kNow), MessageSigner::Verdict::kAuthentic);
  // A receiver started after the recording refuses it within the clock window too.
  // A receiver started after the capture refuses it, however short the time between (traffic
  // captured just before a restart, replayed into the new process).
  MessageSigner restarted(KeyOf(7), 23, kNow + 1);
  EXPECT_EQ(Check(restarted, "ODONATA_CONTROL", old, kNow + 50'000),
            MessageSigner::Verdict::kStale);
  MessageSigner started_at_the_stamp(KeyOf(7), 24, kNow);
  EXPECT_EQ(Check(started_at_the_stamp, "ODONATA_CONTROL", old, kNow + 50'000),
            MessageSigner::Verdict::kAuthentic);
}

TEST(MessageSigner, EachSenderHasItsOwnNewest) {
  MessageSigner one(KeyOf(7), 1), two(KeyOf(7), 2), receiver(KeyOf(7), 3);
  auto a = Payload("a"), b = Payload("b");
  one.Sign("X", &a, kNow + 100);
  two.Sign("X", &b, kNow);  // older than one's, but two's first
  EXPECT_EQ(Check(receiver, "X", a), MessageSigner::Verdict::kAuthentic);
  EXPECT_EQ(Check(receiver, "X", b), MessageSigner::Verdict::kAuthentic);
}

std::string WriteKeyFile(const std::string& text, mode_t mode) {
  char path[] = "/tmp/odonata-key-XXXXXX";
  const int fd = mkstemp(path);
  EXPECT_GE(fd, 0);
  close(fd);
  std::ofstream(path) << text;
  chmod(path, mode);
  return path;
}

TEST(BusKey, AKeyFileMustBeTheOwnersAndHold64HexDigits) {
  const std::string good = WriteKeyFile(NewBusKeyHex() + "\n", 0600);
  EXPECT_NO_THROW(LoadBusKey(good));
  const std::string shared = WriteKeyFile(NewBusKeyHex(), 0644);
  try {
    LoadBusKey(shared);
    ADD_FAILURE() << "a key others can read was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("chmod 600"), std::string::npos) << e.what();
  }
  const std::string short_key = WriteKeyFile("abcdef", 0600);
  EXPECT_THROW(LoadBusKey(short_key), std::runtime_error);
  const std::string not_hex = WriteKeyFile(std::string(64, 'z'), 0600);
  EXPECT_THROW(LoadBusKey(not_hex), std::runtime_error);
  EXPECT_THROW(LoadBusKey("/nonexistent/odonata.key"), std::runtime_error);
  EXPECT_NE(NewBusKeyHex(), NewBusKeyHex());
  for (const auto& p : {good, shared, short_key, not_hex}) std::remove(p.c_str());
}

// A node with the key takes its own signed messages, and refuses — counting each — an unsigned
// one, a mis-signed one and a replayed copy of a signed one; a node without the key still decodes
// the signed message (its trailer lies after the LCM payload).
TEST(BusNodeSigning, OnlyAuthenticNewMessagesReachTheHandlers) {
  const std::string key_path = WriteKeyFile(NewBusKeyHex(), 0600);
  auto options = testing::MemqOptions("odonata-identifier");
  options.key_path = key_path;
  BusNode bus(options);
  ASSERT_TRUE(bus.signing());
  std::vector<int64_t> seen;
  std::vector<uint8_t> last_raw;
  bus.Subscribe<odonata::ack_t>("ACK", [&](const odonata::ack_t& a) { seen.push_back(a.seq); });
  // A second subscription to the same channel gets each authentic message too: the verdict on a
  // message is taken once, not again (as a replay) for the next subscription.
  std::vector<int64_t> seen_too;
  bus.Subscribe<odonata::ack_t>("ACK", [&](const odonata::ack_t& a) { seen_too.push_back(a.seq); });
  bus.SubscribeRaw("RAW", [&](const lcm::ReceiveBuffer& r, const std::string&) {
    last_raw.assign(static_cast<const uint8_t*>(r.data),
                    static_cast<const uint8_t*>(r.data) + r.data_size);
  });
  odonata::ack_t ack{};
  ack.seq = 1;
  ASSERT_TRUE(bus.Publish("ACK", ack));
  testing::Pump(bus, 5);
  EXPECT_EQ(seen, std::vector<int64_t>{1});

  // Signed bytes as a forger would capture them, to send again.
  std::vector<uint8_t> signed_bytes(static_cast<std::size_t>(ack.getEncodedSize()));
  ack.seq = 2;
  ack.encode(signed_bytes.data(), 0, static_cast<int>(signed_bytes.size()));
  const std::vector<uint8_t> unsigned_bytes = signed_bytes;
  MessageSigner same_key(LoadBusKey(key_path), 99);
  same_key.Sign("ACK", &signed_bytes, NowUtime());
  bus.lcm().publish("ACK", signed_bytes.data(), static_cast<unsigned>(signed_bytes.size()));
  bus.lcm().publish("ACK", signed_bytes.data(), static_cast<unsigned>(signed_bytes.size()));
  bus.lcm().publish("ACK", unsigned_bytes.data(), static_cast<unsigned>(unsigned_bytes.size()));
  auto altered = signed_bytes;
  altered[signed_bytes.size() - 1] ^= 0x40;
  bus.lcm().publish("ACK", altered.data(), static_cast<unsigned>(altered.size()));
  bus.lcm().publish("RAW", unsigned_bytes.data(), static_cast<unsigned>(unsigned_bytes.size()));
  testing::Pump(bus, 5);
  EXPECT_EQ(seen, (std::vector<int64_t>{1, 2}));  // the first copy of 2 only
  EXPECT_EQ(seen_too, seen);
  EXPECT_TRUE(last_raw.empty()) << "a raw subscription got an unsigned message";
  EXPECT_EQ(bus.unauthenticated(), 4);
  EXPECT_EQ(bus.stats().dropped, 4);
  EXPECT_NE(bus.stats().last_error.find("refused message on"), std::string::npos);

  // A recorder's subscription gets the authentic message without its signature.
  bus.lcm().publish("RAW", altered.data(), 0);  // an empty datagram: refused as unsigned
  std::vector<uint8_t> raw_signed = unsigned_bytes;
  same_key.Sign("RAW", &raw_signed, NowUtime());
  bus.lcm().publish("RAW", raw_signed.data(), static_cast<unsigned>(raw_signed.size()));
  testing::Pump(bus, 5);
  EXPECT_EQ(last_raw, unsigned_bytes);

  // Without the key: the signed message decodes as it is.
  BusNode keyless(testing::MemqOptions("odonata-monitor"));
  odonata::ack_t decoded{};
  EXPECT_TRUE(SafeDecode(&decoded, signed_bytes.data(), static_cast<int64_t>(signed_bytes.size())));
  EXPECT_EQ(decoded.seq, 2);
  std::remove(key_path.c_str());
}

}  // namespace
}  // namespace odonata::bus

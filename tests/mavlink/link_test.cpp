// What odonata-mavlink adds around the bridge core: frames it writes (frame_encoder) read back by
// the decoder and against the test's own encoder, MAVLink 2 signatures checked with the link's key
// (link_signature), --request-rate's protocol (rate_request), and what the core does with unsigned
// frames and with a second vehicle when a key is given or a plain name is used.
#include <gtest/gtest.h>

#include <sodium.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "mavlink/bridge_core.hpp"
#include "mavlink/frame_decoder.hpp"
#include "mavlink/frame_encoder.hpp"
#include "mavlink/link_signature.hpp"
#include "mavlink/rate_request.hpp"
#include "mavlink_test_support.hpp"

namespace odonata::mavlink {
namespace {

std::vector<Frame> DecodeAll(const std::string& bytes, FrameDecoder& decoder) {
  std::vector<Frame> frames;
  decoder.Feed(bytes, [&frames](const Frame& f) { frames.push_back(f); });
  decoder.Finish([&frames](const Frame& f) { frames.push_back(f); });
  return frames;
}

TEST(FrameEncoder, WritesWhatTheTestsEncoderWritesAndTheDecoderReads) {
  const MessageDef& attitude = *FindByName("ATTITUDE");
  PayloadBuilder p(attitude);
  p.Set("time_boot_ms", 1000).Set("roll", 0.25).Set("pitch", 0.25).Set("yaw", -1.5);
  p.Set("rollspeed", 0.125).Set("pitchspeed", -0.75);
  const std::string frame = EncodeFrameV2(attitude, p.bytes(), 7, 1, 1);
  EXPECT_EQ(frame, test_support::AttitudeFrame(7, 1000, 0.25f, -0.75f));
  EXPECT_THROW(p.Set("nonsense", 1.0), std::invalid_argument);
}

TEST(FrameEncoder, SetMessageIntervalIsACommandLongTheDecoderReads) {
  const std::string frame =
      EncodeFrameV2(*FindByName("COMMAND_LONG"), SetMessageIntervalPayload(1, 1, 30, 10000.0), 3);
  FrameDecoder decoder;
  const std::vector<Frame> frames = DecodeAll(frame, decoder);
  ASSERT_EQ(frames.size(), 1u);
  const Frame& f = frames[0];
  EXPECT_EQ(f.msgid, 76u);
  EXPECT_EQ(f.sysid, kGroundStationSysid);
  EXPECT_EQ(f.compid, kGroundStationCompid);
  EXPECT_EQ(f.seq, 3);
  const auto value = [&f](const char* name) { return Field(f, *FindField(*f.message, name)); };
  EXPECT_EQ(value("command"), 511.0);
  EXPECT_EQ(value("param1"), 30.0);
  EXPECT_EQ(value("param2"), 10000.0);
  EXPECT_EQ(value("target_system"), 1.0);
  EXPECT_EQ(value("target_component"), 1.0);
  EXPECT_EQ(decoder.counters().dropped(), 0u);
}

// A signed frame as a signing sender writes it: the frame with incompat bit 0, link id, a
// 48-bit timestamp, and the first 6 bytes of SHA-256(key + everything before them).
std::string SignedAttitude(const LinkKey& key, std::uint8_t seq) {
  test_support::FrameSpec spec;
  spec.msgid = 30;
  spec.payload = test_support::AttitudePayload(10, 0.25f, 0.5f, -1.5f, 0.125f, 0.75f, 0.0f);
  spec.seq = seq;
  spec.incompat = kIncompatSigned;
  spec.signature = std::string("\x01\x10\x20\x30\x40\x50\x60", 7);  // link id, timestamp
  std::string frame = test_support::EncodeFrame(spec);
  // Independent of LinkSignature: libsodium's one-shot SHA-256 over key and frame.
  std::string message(key.begin(), key.end());
  message += frame;
  unsigned char digest[crypto_hash_sha256_BYTES];
  crypto_hash_sha256(digest, reinterpret_cast<const unsigned char*>(message.data()),
                     message.size());
  frame.append(reinterpret_cast<const char*>(digest), 6);
  return frame;
}

TEST(LinkSignature, TheLinksKeyPassesItsFramesAndRefusesOthers) {
  ASSERT_GE(sodium_init(), 0);
  LinkKey key{};
  for (std::size_t i = 0; i < key.size(); ++i) key[i] = static_cast<std::uint8_t>(i * 7 + 1);
  LinkKey other = key;
  other[0] ^= 1;
  const std::string frame = SignedAttitude(key, 1);
  FrameDecoder right(SignatureCheckFor(key));
  EXPECT_EQ(DecodeAll(frame, right).size(), 1u);
  EXPECT_EQ(right.counters().signed_frames, 1u);
  FrameDecoder wrong(SignatureCheckFor(other));
  EXPECT_EQ(DecodeAll(frame, wrong).size(), 0u);
  EXPECT_EQ(wrong.counters().bad_signature, 1u);
  std::string tampered = frame;
  tampered[tampered.size() - 1] = static_cast<char>(tampered.back() ^ 1);
  FrameDecoder check(SignatureCheckFor(key));
  EXPECT_EQ(DecodeAll(tampered, check).size(), 0u);
  EXPECT_EQ(check.counters().bad_signature, 1u);
}

TEST(LinkSignature, FramesSignedHerePassTheLinksCheckAndNoOther) {
  LinkKey key{};
  key[3] = 0x42;
  LinkKey other = key;
  other[3] = 0x43;
  const std::string plain =
      EncodeFrameV2(*FindByName("COMMAND_LONG"), SetMessageIntervalPayload(1, 1, 30, 10000.0), 9);
  const std::string a = SignFrameV2(plain, key, 2, 1000);
  const std::string b = SignFrameV2(plain, key, 2, 1001);
  EXPECT_EQ(a.size(), plain.size() + kSignatureSize);
  EXPECT_NE(a, b);  // the timestamp is signed
  FrameDecoder right(SignatureCheckFor(key));
  const std::vector<Frame> frames = DecodeAll(a + b, right);
  ASSERT_EQ(frames.size(), 2u);
  EXPECT_TRUE(frames[0].is_signed());
  EXPECT_EQ(Field(frames[0], *FindField(*frames[0].message, "param2")), 10000.0);
  EXPECT_EQ(right.counters().signed_frames, 2u);
  FrameDecoder wrong(SignatureCheckFor(other));
  EXPECT_TRUE(DecodeAll(a, wrong).empty());
  EXPECT_EQ(wrong.counters().bad_signature, 1u);
  EXPECT_THROW(SignFrameV2(a, key, 2, 1002), std::invalid_argument);  // signed already
  EXPECT_THROW(SignFrameV2(plain.substr(0, 12), key, 2, 1002), std::invalid_argument);
  EXPECT_GT(SigningTimestampNow(), std::uint64_t{1} << 40);  // years past 2015, in 10 µs
}

TEST(LinkSignature, KeyFilesAreReadOrRefusedWithTheReason) {
  const auto dir = std::filesystem::temp_directory_path() / "odonata_link_key_test";
  std::filesystem::create_directories(dir);
  const std::string good = (dir / "good").string(), bad = (dir / "bad").string();
  std::ofstream(good) << "000102030405060708090a0b0c0d0e0f\n101112131415161718191a1b1c1d1e1f\n";
  std::ofstream(bad) << "not a key";
  const LinkKey key = ReadLinkKey(good);
  EXPECT_EQ(key[0], 0);
  EXPECT_EQ(key[31], 0x1f);
  try {
    ReadLinkKey(bad);
    ADD_FAILURE() << "a file of no key was taken";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("64 hex digits"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ReadLinkKey((dir / "missing").string()), std::runtime_error);
  std::filesystem::remove_all(dir);
}

TEST(BridgeWithKey, UnsignedFramesAreRefusedAndCountedSignedOnesTaken) {
  LinkKey key{};
  key[5] = 9;
  BridgeOptions o;
  o.fields = {"ATTITUDE.pitchspeed"};
  o.rate_hz = 10.0;
  o.signature_check = SignatureCheckFor(key);
  o.unsigned_frames = UnsignedFrames::kRefuse;
  BridgeCore core(o);
  for (int i = 0; i < 10; ++i) {
    core.Feed(SignedAttitude(key, static_cast<std::uint8_t>(i)), 0.1 * i);
    core.Feed(test_support::AttitudeFrame(static_cast<std::uint8_t>(i), 0, 0.0f, 100.0f),
              0.1 * i + 0.01);
  }
  const std::vector<GridSample> samples = core.TakeSamples();
  ASSERT_FALSE(samples.empty());
  for (const GridSample& s : samples) EXPECT_EQ(s.values[0], 0.75) << s.k;
  EXPECT_EQ(core.unsigned_refused(), 10u);
  EXPECT_EQ(core.bridge_dropped(), 10u);
}

TEST(BridgeOtherSenders, ASecondVehicleIsNamedForItsMessage) {
  BridgeOptions o;
  o.fields = {"ATTITUDE.pitch"};
  o.rate_hz = 10.0;
  BridgeCore core(o);
  core.Feed(test_support::AttitudeFrame(0, 0, 0.1f, 0.0f, 1, 1), 0.0);
  core.Feed(test_support::AttitudeFrame(0, 0, 100.0f, 0.0f, 2, 1), 0.01);
  core.Feed(test_support::AttitudeFrame(1, 0, 0.1f, 0.0f, 1, 1), 0.1);
  ASSERT_EQ(core.other_senders().count("ATTITUDE"), 1u);
  EXPECT_EQ(core.other_senders().at("ATTITUDE"), std::set<std::string>{"2:1"});
}

TEST(RateRequest, ParsesMessageAndRateOrSaysWhatIsWrong) {
  const RateRequest r = ParseRateRequest("ATTITUDE=100");
  EXPECT_EQ(r.message, "ATTITUDE");
  EXPECT_EQ(r.message_id, 30u);
  EXPECT_EQ(r.rate_hz, 100.0);
  for (const char* bad : {"ATTITUDE", "NOPE=10", "ATTITUDE=0", "ATTITUDE=-5", "ATTITUDE=fast",
                          "ATTITUDE=1e9", "ATTITUDE="})
    EXPECT_THROW(ParseRateRequest(bad), std::invalid_argument) << bad;
}

Frame HeardFrame(const std::string& bytes) {
  FrameDecoder decoder;
  const std::vector<Frame> frames = DecodeAll(bytes, decoder);
  EXPECT_EQ(frames.size(), 1u);
  return frames.at(0);
}

std::string AckFrame(std::uint16_t command, std::uint8_t result) {
  const MessageDef& ack = *FindByName("COMMAND_ACK");
  PayloadBuilder p(ack);
  p.Set("command", command).Set("result", result);
  return EncodeFrameV2(ack, p.bytes(), 0, 1, 1);
}

TEST(RateRequester, SendsOnceHeardResendsUntilAnsweredAndGivesUp) {
  RateRequester r({ParseRateRequest("ATTITUDE=50"), ParseRateRequest("HIGHRES_IMU=200")}, 1, 1);
  EXPECT_TRUE(r.Due(0.0).empty()) << "sent before the vehicle was heard";
  r.Observe(HeardFrame(test_support::AttitudeFrame(0, 0, 0.0f, 0.0f, 2, 1)));
  EXPECT_TRUE(r.Due(0.1).empty()) << "another vehicle is not the target";
  r.Observe(HeardFrame(test_support::AttitudeFrame(0, 0, 0.0f, 0.0f, 1, 1)));
  const std::vector<std::string> first = r.Due(0.2);
  ASSERT_EQ(first.size(), 2u);
  const Frame sent = HeardFrame(first[0]);
  EXPECT_EQ(Field(sent, *FindField(*sent.message, "param2")), 20000.0);
  EXPECT_TRUE(r.Due(0.3).empty()) << "resent before kResendS";
  // The first request is answered (acks answer in the order sent); the second is not.
  r.Observe(HeardFrame(AckFrame(kCmdSetMessageInterval, 0)));
  const std::vector<std::string> again = r.Due(0.2 + kResendS);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(Field(HeardFrame(again[0]), *FindField(*FindByName("COMMAND_LONG"), "param1")), 105.0);
  EXPECT_EQ(r.Due(0.2 + 2 * kResendS).size(), 1u);
  EXPECT_TRUE(r.Due(0.2 + 3 * kResendS).empty()) << "more than kMaxAttempts tries";
  const std::vector<std::string> status = r.Status();
  ASSERT_EQ(status.size(), 2u);
  EXPECT_EQ(status[0], "ATTITUDE at 50 Hz: accepted");
  EXPECT_EQ(status[1], "HIGHRES_IMU at 200 Hz: no answer after 3 tries");
}

TEST(RateRequester, ARefusalIsSaidWithItsResult) {
  RateRequester r({ParseRateRequest("ATTITUDE=50")}, 1, 1);
  r.Observe(HeardFrame(test_support::AttitudeFrame(0, 0, 0.0f, 0.0f)));
  ASSERT_EQ(r.Due(0.0).size(), 1u);
  r.Observe(HeardFrame(AckFrame(400, 0)));  // another command's answer
  r.Observe(HeardFrame(AckFrame(kCmdSetMessageInterval, 4)));
  EXPECT_EQ(r.Status()[0], "ATTITUDE at 50 Hz: refused (MAV_RESULT 4)");
  EXPECT_TRUE(r.Due(10.0).empty());
}

}  // namespace
}  // namespace odonata::mavlink

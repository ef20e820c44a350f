// The MAVLink frame decoder on frames encoded apart (mavlink_test_support.hpp): MAVLink 1 and 2,
// payloads cut of their trailing zeros, a stream split at every byte, and what it drops and
// counts: bad checksums (with resynchronisation), unknown messages, incompatible flags, signed
// frames, noise, a frame cut at the end, and sequence gaps per sender.
#include <gtest/gtest.h>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "mavlink/frame_decoder.hpp"
#include "mavlink/mavlink_messages.hpp"
#include "mavlink_test_support.hpp"

namespace odonata::mavlink {
namespace {

using test_support::AttitudeFrame;
using test_support::EncodeFrame;
using test_support::FrameSpec;
using test_support::UnknownFrame;

struct DecodedStream {
  std::vector<Frame> frames;
  DecoderCounters counters;
  std::map<std::uint16_t, SenderStats> senders;
  std::size_t lost = 0;
};

// `bytes` fed in pieces ending at each of `cuts` (ascending), then the rest, then Finish.
DecodedStream DecodeInPieces(const std::string& bytes, const std::vector<std::size_t>& cuts,
                             FrameDecoder::SignatureCheck check = {}) {
  FrameDecoder decoder(std::move(check));
  DecodedStream out;
  const FrameDecoder::FrameHandler keep = [&out](const Frame& f) { out.frames.push_back(f); };
  std::size_t from = 0;
  for (const std::size_t cut : cuts) {
    decoder.Feed(std::string_view(bytes).substr(from, cut - from), keep);
    from = cut;
  }
  decoder.Feed(std::string_view(bytes).substr(from), keep);
  decoder.Finish(keep);
  out.counters = decoder.counters();
  out.senders = decoder.sequences().senders();
  out.lost = decoder.sequences().lost();
  return out;
}

DecodedStream DecodeWholeStream(const std::string& bytes) { return DecodeInPieces(bytes, {}); }

// Field `name` of a decoded frame of a known message.
double FrameValue(const Frame& f, const char* name) {
  const std::optional<FieldRef> ref = FindField(*f.message, name);
  EXPECT_TRUE(ref.has_value()) << name;
  return ref ? Field(f, *ref) : -1e300;
}

void ExpectSameDecoding(const DecodedStream& a, const DecodedStream& b) {
  ASSERT_EQ(a.frames.size(), b.frames.size());
  for (std::size_t i = 0; i < a.frames.size(); ++i) {
    EXPECT_EQ(a.frames[i].msgid, b.frames[i].msgid) << i;
    EXPECT_EQ(a.frames[i].seq, b.frames[i].seq) << i;
    EXPECT_EQ(a.frames[i].payload, b.frames[i].payload) << i;
  }
  const DecoderCounters& x = a.counters;
  const DecoderCounters& y = b.counters;
  EXPECT_EQ(x.frames_ok, y.frames_ok);
  EXPECT_EQ(x.v1_frames, y.v1_frames);
  EXPECT_EQ(x.signed_frames, y.signed_frames);
  EXPECT_EQ(x.truncated, y.truncated);
  EXPECT_EQ(x.bad_crc, y.bad_crc);
  EXPECT_EQ(x.unknown_message, y.unknown_message);
  EXPECT_EQ(x.incompatible, y.incompatible);
  EXPECT_EQ(x.cut, y.cut);
  EXPECT_EQ(x.bytes_skipped, y.bytes_skipped);
  EXPECT_EQ(a.lost, b.lost);
}

TEST(FrameDecoder, DecodesAMavlink2Frame) {
  const std::string bytes = AttitudeFrame(7, 123456, 0.25f, -0.75f, 3, 4);
  const DecodedStream s = DecodeWholeStream(bytes);
  ASSERT_EQ(s.frames.size(), 1u);
  const Frame& f = s.frames[0];
  EXPECT_EQ(f.version, 2);
  EXPECT_EQ(f.msgid, 30u);
  EXPECT_EQ(f.seq, 7);
  EXPECT_EQ(f.sysid, 3);
  EXPECT_EQ(f.compid, 4);
  ASSERT_NE(f.message, nullptr);
  EXPECT_EQ(f.message->name, "ATTITUDE");
  EXPECT_EQ(f.size, bytes.size());
  EXPECT_FALSE(f.is_signed());
  EXPECT_EQ(FrameValue(f, "time_boot_ms"), 123456.0);
  EXPECT_EQ(FrameValue(f, "roll"), 0.25);
  EXPECT_EQ(FrameValue(f, "pitch"), 0.25);
  EXPECT_EQ(FrameValue(f, "yaw"), -1.5);
  EXPECT_EQ(FrameValue(f, "rollspeed"), 0.125);
  EXPECT_EQ(FrameValue(f, "pitchspeed"), -0.75);
  // yawspeed is 0: MAVLink 2 cut its four bytes, the decoder put them back.
  EXPECT_EQ(f.wire_length, 24u);
  EXPECT_TRUE(f.truncated());
  EXPECT_EQ(FrameValue(f, "yawspeed"), 0.0);
  EXPECT_EQ(s.counters.frames_ok, 1u);
  EXPECT_EQ(s.counters.truncated, 1u);
  EXPECT_EQ(s.counters.bytes_skipped, 0u);
  EXPECT_EQ(s.counters.dropped(), 0u);
}

TEST(FrameDecoder, DecodesAMavlink1FrameWithoutExtensions) {
  FrameSpec spec;
  spec.version = 1;
  spec.msgid = 36;
  spec.seq = 200;
  spec.payload =
      test_support::ServoPayload(4242, 1, {1100, 1200, 1300, 1400, 1500, 1600, 1700, 1800});
  const std::string bytes = EncodeFrame(spec);
  EXPECT_EQ(bytes.size(), 6u + 21u + 2u);
  const DecodedStream s = DecodeWholeStream(bytes);
  ASSERT_EQ(s.frames.size(), 1u);
  const Frame& f = s.frames[0];
  EXPECT_EQ(f.version, 1);
  EXPECT_EQ(f.msgid, 36u);
  EXPECT_EQ(f.seq, 200);
  EXPECT_EQ(f.wire_length, 21u);
  EXPECT_EQ(FrameValue(f, "time_usec"), 4242.0);
  EXPECT_EQ(FrameValue(f, "servo1_raw"), 1100.0);
  EXPECT_EQ(FrameValue(f, "servo3_raw"), 1300.0);
  EXPECT_EQ(FrameValue(f, "servo8_raw"), 1800.0);
  EXPECT_EQ(FrameValue(f, "port"), 1.0);
  EXPECT_EQ(FrameValue(f, "servo12_raw"), 0.0);  // no extensions in MAVLink 1
  EXPECT_EQ(s.counters.v1_frames, 1u);
}

TEST(FrameDecoder, ReadsArraysAnd24BitMessageIds) {
  FrameSpec spec;
  spec.msgid = 375;
  spec.payload = test_support::ActuatorPayload(9'000'000'000ull, {0.5f, -0.25f, 1.0f});
  const DecodedStream s = DecodeWholeStream(EncodeFrame(spec));
  ASSERT_EQ(s.frames.size(), 1u);
  const Frame& f = s.frames[0];
  EXPECT_EQ(f.msgid, 375u);
  EXPECT_EQ(FrameValue(f, "time_usec"), 9e9);
  EXPECT_EQ(FrameValue(f, "active"), 3.0);
  EXPECT_EQ(FrameValue(f, "actuator[0]"), 0.5);
  EXPECT_EQ(FrameValue(f, "actuator[1]"), -0.25);
  EXPECT_EQ(FrameValue(f, "actuator[2]"), 1.0);
  EXPECT_EQ(FrameValue(f, "actuator[31]"), 0.0);
  EXPECT_EQ(f.wire_length, 24u);  // cut after actuator[2]
}

TEST(FrameDecoder, AllZeroPayloadKeepsOneByte) {
  FrameSpec spec;
  spec.msgid = 30;
  spec.payload = std::string(28, '\0');
  const std::string bytes = EncodeFrame(spec);
  EXPECT_EQ(bytes.size(), 10u + 1u + 2u);
  const DecodedStream s = DecodeWholeStream(bytes);
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_EQ(s.frames[0].wire_length, 1u);
  EXPECT_EQ(FrameValue(s.frames[0], "pitch"), 0.0);
}

// Every kind of frame and some noise, in one stream.
std::string MixedStream() {
  std::string bytes = AttitudeFrame(0, 1000, 0.1f, 0.2f);
  FrameSpec servo;
  servo.version = 1;
  servo.msgid = 36;
  servo.seq = 1;
  servo.payload =
      test_support::ServoPayload(5, 0, {1500, 1500, 1510, 1500, 1500, 1500, 1500, 1500});
  bytes += EncodeFrame(servo);
  FrameSpec heartbeat;
  heartbeat.msgid = 0;
  heartbeat.seq = 2;
  heartbeat.incompat = 1;
  heartbeat.payload = test_support::HeartbeatPayload(19, 12, 81);
  bytes += EncodeFrame(heartbeat);
  bytes += UnknownFrame(3);
  FrameSpec actuators;
  actuators.msgid = 375;
  actuators.seq = 4;
  actuators.payload = test_support::ActuatorPayload(77, {0.5f, 0.75f});
  bytes += EncodeFrame(actuators);
  bytes += std::string("\x01\x02", 2);
  bytes += AttitudeFrame(5, 1100, 0.15f, 0.25f);
  return bytes;
}

TEST(FrameDecoder, AStreamSplitAtAnyByteDecodesTheSame) {
  const std::string bytes = MixedStream();
  const DecodedStream whole = DecodeWholeStream(bytes);
  ASSERT_EQ(whole.frames.size(), 5u);
  EXPECT_EQ(whole.frames[1].version, 1);
  EXPECT_TRUE(whole.frames[2].is_signed());
  EXPECT_EQ(FrameValue(whole.frames[2], "custom_mode"), 19.0);
  EXPECT_EQ(FrameValue(whole.frames[3], "actuator[1]"), 0.75);
  EXPECT_EQ(whole.counters.frames_ok, 5u);
  EXPECT_EQ(whole.counters.v1_frames, 1u);
  EXPECT_EQ(whole.counters.signed_frames, 1u);
  EXPECT_EQ(whole.counters.unknown_message, 1u);
  EXPECT_EQ(whole.counters.bytes_skipped, 2u);
  EXPECT_EQ(whole.counters.bad_crc, 0u);
  EXPECT_EQ(whole.lost, 0u);
  for (std::size_t k = 0; k <= bytes.size(); ++k) {
    SCOPED_TRACE(k);
    ExpectSameDecoding(DecodeInPieces(bytes, {k}), whole);
  }
  std::vector<std::size_t> every_byte;
  for (std::size_t k = 1; k < bytes.size(); ++k) every_byte.push_back(k);
  ExpectSameDecoding(DecodeInPieces(bytes, every_byte), whole);
}

TEST(FrameDecoder, ABadChecksumIsCountedOnceAndTheNextFrameRead) {
  const std::string first = AttitudeFrame(0, 1000, 0.1f, 0.2f);
  std::string second = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  second[14] = static_cast<char>(second[14] ^ 0x40);  // a payload byte
  const std::string third = AttitudeFrame(2, 1200, 0.5f, 0.6f);
  const DecodedStream s = DecodeWholeStream(first + second + third);
  ASSERT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.frames[0].seq, 0);
  EXPECT_EQ(s.frames[1].seq, 2);
  EXPECT_EQ(s.counters.bad_crc, 1u);
  EXPECT_EQ(s.counters.bytes_skipped, second.size());
  // The lost frame shows in its sender's sequence too.
  const SenderStats& sender = s.senders.at(SenderKey(1, 1));
  EXPECT_EQ(sender.frames, 2u);
  EXPECT_EQ(sender.gaps, 1u);
  EXPECT_EQ(sender.lost, 1u);
}

TEST(FrameDecoder, AFrameBehindACorruptedLengthIsFound) {
  const std::string first = AttitudeFrame(0, 1000, 0.1f, 0.2f);
  std::string longer = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  longer[1] = static_cast<char>(longer[1] + 5);  // the checksum then covers the next frame's bytes
  const std::string third = AttitudeFrame(2, 1200, 0.5f, 0.6f);
  const std::string fourth = AttitudeFrame(3, 1300, 0.7f, 0.8f);
  const DecodedStream s = DecodeWholeStream(first + longer + third + fourth);
  ASSERT_EQ(s.frames.size(), 3u);
  EXPECT_EQ(s.frames[1].seq, 2);
  EXPECT_EQ(s.counters.bad_crc, 1u);
  EXPECT_EQ(s.counters.bytes_skipped, longer.size());

  // The length points past the end of the datagram: Finish finds the frame behind it.
  std::string past_the_end = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  past_the_end[1] = static_cast<char>(200);
  const DecodedStream d = DecodeWholeStream(first + past_the_end + third);
  ASSERT_EQ(d.frames.size(), 2u);
  EXPECT_EQ(d.frames[1].seq, 2);
  EXPECT_EQ(d.counters.cut, 1u);
  EXPECT_EQ(d.counters.bad_crc, 0u);
  EXPECT_EQ(d.counters.bytes_skipped, past_the_end.size());
}

TEST(FrameDecoder, UnknownMessagesAreCountedAndDropped) {
  const std::string bytes = AttitudeFrame(0, 1000, 0.1f, 0.2f) + UnknownFrame(1) + UnknownFrame(2) +
                            AttitudeFrame(3, 1100, 0.3f, 0.4f);
  const DecodedStream s = DecodeWholeStream(bytes);
  ASSERT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.counters.unknown_message, 2u);
  EXPECT_EQ(s.counters.unknown_ids.at(178), 2u);
  EXPECT_EQ(s.counters.bytes_skipped, 0u);
  EXPECT_EQ(s.counters.dropped(), 2u);
  EXPECT_EQ(s.lost, 0u);  // their sequence numbers are followed
  // A stream is taken to start at a frame: one of an unknown message first is trusted too.
  EXPECT_EQ(DecodeWholeStream(UnknownFrame(0) + AttitudeFrame(1, 0, 0, 0)).counters.unknown_message,
            1u);
}

TEST(FrameDecoder, AfterNoiseUnknownMessagesAreSkippedWithIt) {
  const std::string noise("\x00\x13\x37", 3);
  const std::string unknown = UnknownFrame(0);
  const DecodedStream s = DecodeWholeStream(noise + unknown + AttitudeFrame(1, 1000, 0.1f, 0.2f));
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_EQ(s.counters.unknown_message, 0u);
  EXPECT_EQ(s.counters.bytes_skipped, noise.size() + unknown.size());
  EXPECT_EQ(s.counters.bad_crc, 0u);
}

TEST(FrameDecoder, NoiseBetweenFramesIsSkipped) {
  const DecodedStream s = DecodeWholeStream(AttitudeFrame(0, 1000, 0.1f, 0.2f) + "hello" +
                                            AttitudeFrame(1, 1100, 0.3f, 0.4f));
  EXPECT_EQ(s.frames.size(), 2u);
  EXPECT_EQ(s.counters.bytes_skipped, 5u);
  EXPECT_EQ(s.counters.dropped(), 0u);
}

TEST(FrameDecoder, SequenceGapsAreCountedPerSender) {
  std::string bytes;
  for (const int seq : {0, 1, 2, 5, 6})
    bytes += AttitudeFrame(static_cast<std::uint8_t>(seq), 0, 0, 0, 1, 1);
  for (const int seq : {254, 255, 0, 1})
    bytes += AttitudeFrame(static_cast<std::uint8_t>(seq), 0, 0, 0, 2, 1);
  bytes += AttitudeFrame(10, 0, 0, 0, 1, 1);
  const DecodedStream s = DecodeWholeStream(bytes);
  EXPECT_EQ(s.frames.size(), 10u);
  const SenderStats& a = s.senders.at(SenderKey(1, 1));
  EXPECT_EQ(a.frames, 6u);
  EXPECT_EQ(a.gaps, 2u);
  EXPECT_EQ(a.lost, 2u + 3u);  // 3, 4 and 7, 8, 9
  const SenderStats& b = s.senders.at(SenderKey(2, 1));
  EXPECT_EQ(b.frames, 4u);
  EXPECT_EQ(b.gaps, 0u);  // 255 wraps to 0
  EXPECT_EQ(s.lost, 5u);
}

TEST(FrameDecoder, SignedFramesAreSkippedOrChecked) {
  FrameSpec spec;
  spec.msgid = 0;
  spec.incompat = 1;
  spec.payload = test_support::HeartbeatPayload(7, 2, 81);
  const std::string signed_frame = EncodeFrame(spec);
  EXPECT_EQ(signed_frame.size(), 10u + 9u + 2u + 13u);
  const std::string bytes = signed_frame + AttitudeFrame(1, 1000, 0.1f, 0.2f);

  const DecodedStream skipped = DecodeWholeStream(bytes);
  ASSERT_EQ(skipped.frames.size(), 2u);
  EXPECT_TRUE(skipped.frames[0].is_signed());
  EXPECT_EQ(FrameValue(skipped.frames[0], "custom_mode"), 7.0);
  EXPECT_EQ(skipped.counters.signed_frames, 1u);

  std::vector<std::string> asked;
  const DecodedStream refused = DecodeInPieces(bytes, {}, [&asked](std::string_view frame_bytes) {
    asked.emplace_back(frame_bytes);
    return false;
  });
  ASSERT_EQ(asked.size(), 1u);  // unsigned frames are not asked about
  EXPECT_EQ(asked[0], signed_frame);
  ASSERT_EQ(refused.frames.size(), 1u);
  EXPECT_EQ(refused.frames[0].msgid, 30u);
  EXPECT_EQ(refused.counters.bad_signature, 1u);
  EXPECT_EQ(refused.counters.signed_frames, 0u);

  const DecodedStream accepted = DecodeInPieces(bytes, {}, [](std::string_view) { return true; });
  EXPECT_EQ(accepted.frames.size(), 2u);
  EXPECT_EQ(accepted.counters.signed_frames, 1u);
}

TEST(FrameDecoder, UnknownIncompatibleFlagsDropTheFrame) {
  FrameSpec spec;
  spec.msgid = 30;
  spec.incompat = 0x02;
  spec.payload = test_support::AttitudePayload(1, 1, 1, 1, 1, 1, 1);
  const DecodedStream s = DecodeWholeStream(EncodeFrame(spec) + AttitudeFrame(1, 1000, 0.1f, 0.2f));
  ASSERT_EQ(s.frames.size(), 1u);
  EXPECT_EQ(s.frames[0].seq, 1);
  EXPECT_EQ(s.counters.incompatible, 1u);
  EXPECT_EQ(s.counters.bytes_skipped, 0u);
}

TEST(FrameDecoder, AFrameCutByTheEndOfTheStreamIsCounted) {
  const std::string whole = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  const std::string cut = whole.substr(0, whole.size() - 3);
  FrameDecoder decoder;
  std::size_t frames = 0;
  const FrameDecoder::FrameHandler count = [&frames](const Frame&) { ++frames; };
  decoder.Feed(AttitudeFrame(0, 1000, 0.1f, 0.2f) + cut, count);
  EXPECT_EQ(frames, 1u);
  EXPECT_EQ(decoder.counters().cut, 0u);  // more may come
  decoder.Finish(count);
  EXPECT_EQ(frames, 1u);
  EXPECT_EQ(decoder.counters().cut, 1u);
  EXPECT_EQ(decoder.counters().bytes_skipped, cut.size());
  EXPECT_TRUE(decoder.synchronised());
  // The next datagram starts afresh.
  decoder.Feed(whole, count);
  EXPECT_EQ(frames, 2u);
  EXPECT_EQ(decoder.counters().frames_ok, 2u);
}

}  // namespace
}  // namespace odonata::mavlink

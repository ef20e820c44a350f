// The telemetry log reader on logs written apart (mavlink_test_support.hpp): every record of a
// small flight, told by content, cut at every byte (a clean partial read), and damaged: noise
// between records, a frame failing its checksum, a timestamp outside the century, incompatible
// flags, a clock going back.
#include <gtest/gtest.h>

#include <cstdint>
#include <string>
#include <vector>

#include "mavlink/mavlink_messages.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink_test_support.hpp"

namespace odonata::mavlink {
namespace {

using test_support::AttitudeFrame;
using test_support::kT0Us;
using test_support::SmallFlightTlog;
using test_support::TlogWriter;
using test_support::UnknownFrame;

// Field `field` of frame `i` of `series`.
double SeriesValue(const MessageSeries& series, std::size_t i, const char* field) {
  return series.Value(i, *FindField(*series.message, field));
}

TEST(TlogFile, ReadsEveryRecordOfASmallFlight) {
  const TlogWriter w = SmallFlightTlog();
  const TlogFile f = Parse(w.bytes(), "flight.tlog");
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.source, "flight.tlog");
  EXPECT_EQ(f.file_size, w.size());
  EXPECT_EQ(f.records, 15u);
  EXPECT_EQ(f.first_time_us, kT0Us);
  EXPECT_EQ(f.last_time_us, kT0Us + 403'000);
  EXPECT_EQ(f.frame_counts.at(30), 5u);
  EXPECT_EQ(f.frame_counts.at(36), 3u);
  EXPECT_EQ(f.frame_counts.at(0), 5u);
  EXPECT_EQ(f.frame_counts.at(178), 2u);
  EXPECT_EQ(f.unknown_frames, 2u);
  EXPECT_EQ(f.unknown_counts.at(178), 2u);
  EXPECT_EQ(f.v1_frames, 1u);
  EXPECT_EQ(f.signed_frames, 1u);
  EXPECT_EQ(f.bad_crc, 0u);
  EXPECT_EQ(f.incompatible, 0u);
  EXPECT_EQ(f.bytes_skipped, 0u);
  EXPECT_EQ(f.damage_count, 0u);
  EXPECT_TRUE(f.notes.empty());
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 5u);
  EXPECT_EQ(f.FrameCount("HEARTBEAT"), 5u);
  EXPECT_EQ(f.FrameCount("SERVO_OUTPUT_RAW"), 3u);
  EXPECT_EQ(f.FrameCount("AHRS2"), 0u);

  // Per message and sender, sorted by name, then sender.
  ASSERT_EQ(f.series.size(), 4u);
  EXPECT_EQ(f.series[0].message->name, "ATTITUDE");
  EXPECT_EQ(f.series[1].message->name, "HEARTBEAT");
  EXPECT_EQ(f.series[1].sender(), "1:1");
  EXPECT_EQ(f.series[2].sender(), "255:190");
  EXPECT_EQ(f.series[3].message->name, "SERVO_OUTPUT_RAW");
  ASSERT_NE(f.FindMain("HEARTBEAT"), nullptr);
  EXPECT_EQ(f.FindMain("HEARTBEAT")->sysid, 1);  // 3 frames against the ground station's 2
  ASSERT_NE(f.Find("HEARTBEAT", 255, 190), nullptr);
  EXPECT_EQ(f.Find("HEARTBEAT", 255, 190)->size(), 2u);
  EXPECT_EQ(f.Find("HEARTBEAT", 2, 1), nullptr);
  EXPECT_EQ(f.FindMain("HIGHRES_IMU"), nullptr);

  const MessageSeries& servo = *f.Find("SERVO_OUTPUT_RAW", 1, 1);
  ASSERT_EQ(servo.size(), 3u);
  EXPECT_EQ(servo.payloads.size(), 3u * 37u);  // zero-extended to the whole message
  EXPECT_EQ(servo.times_us[1], kT0Us + 202'000);
  EXPECT_EQ(SeriesValue(servo, 0, "servo3_raw"), 1501.0);
  EXPECT_EQ(SeriesValue(servo, 2, "servo3_raw"), 1541.0);
  EXPECT_EQ(SeriesValue(servo, 0, "servo12_raw"), 1100.0);
  EXPECT_EQ(SeriesValue(servo, 2, "servo12_raw"), 0.0);  // MAVLink 1: no extensions
  EXPECT_EQ(servo.truncated, 3u);  // two cut of trailing zeros, one without extensions
  const MessageSeries& attitude = *f.Find("ATTITUDE", 1, 1);
  EXPECT_EQ(SeriesValue(attitude, 3, "pitchspeed"), 2.5);
  EXPECT_EQ(SeriesValue(attitude, 3, "time_boot_ms"), 1300.0);

  const auto& senders = f.sequences.senders();
  EXPECT_EQ(senders.at(SenderKey(1, 1)).frames, 13u);  // unknown messages' numbers count too
  EXPECT_EQ(senders.at(SenderKey(255, 190)).frames, 2u);
  EXPECT_EQ(f.sequences.lost(), 0u);
}

TEST(TlogFile, IsToldByItsContent) {
  const std::string log = SmallFlightTlog().bytes();
  EXPECT_TRUE(LooksLikeTlog(log.substr(0, 16)));
  EXPECT_TRUE(LooksLikeTlog(log.substr(0, 9)));
  EXPECT_FALSE(LooksLikeTlog(log.substr(0, 8)));
  EXPECT_FALSE(LooksLikeTlog(std::string("ULog\x01\x12\x35\x01", 8) + std::string(8, '\0')));
  EXPECT_FALSE(LooksLikeTlog(std::string{'\xA3', '\x95', '\x80'} + std::string(13, 'x')));
  EXPECT_FALSE(LooksLikeTlog("t_s,roll\n0,1\n1,2\n"));
  const auto head = [](std::uint64_t t_us, int version) {
    TlogWriter w;
    test_support::FrameSpec spec;
    spec.version = version;
    spec.payload = test_support::AttitudePayload(1, 1, 1, 1, 1, 1, 1);
    w.Record(t_us, test_support::EncodeFrame(spec));
    return w.bytes();
  };
  EXPECT_TRUE(LooksLikeTlog(head(kT0Us, 2)));
  EXPECT_TRUE(LooksLikeTlog(head(kT0Us, 1)));
  EXPECT_TRUE(LooksLikeTlog(head(kEarliestTlogTimeUs, 2)));  // 2000-01-01
  EXPECT_FALSE(LooksLikeTlog(head(kEarliestTlogTimeUs - 1, 2)));
  EXPECT_FALSE(LooksLikeTlog(head(kLatestTlogTimeUs, 2)));  // 2100-01-01
  EXPECT_FALSE(LooksLikeTlog(head(0, 2)));
}

TEST(TlogFile, WhatIsNoTelemetryLogThrows) {
  EXPECT_THROW(Parse("", "empty.tlog"), TlogError);
  EXPECT_THROW(Read("/no/such/dir/flight.tlog"), TlogError);
  try {
    (void)Parse("t_s,roll\n0,1\n", "flight.csv");
    ADD_FAILURE() << "a CSV read as a telemetry log";
  } catch (const TlogError& e) {
    EXPECT_NE(std::string(e.what()).find("flight.csv: not a MAVLink telemetry log"),
              std::string::npos)
        << e.what();
  }
}

TEST(TlogFile, ACutLogReadsEveryWholeRecord) {
  const TlogWriter w = SmallFlightTlog();
  const std::string& bytes = w.bytes();
  const std::vector<std::size_t>& starts = w.record_starts();
  for (std::size_t n = 1; n <= 8; ++n)
    EXPECT_THROW(Parse(bytes.substr(0, n), "cut.tlog"), TlogError) << n;
  for (std::size_t n = 9; n <= bytes.size(); ++n) {
    SCOPED_TRACE(n);
    const TlogFile f = Parse(bytes.substr(0, n), "cut.tlog");
    // The records that end within the cut are read; the one it cuts is reported at its start.
    std::size_t whole = 0;
    while (whole < starts.size() &&
           (whole + 1 < starts.size() ? starts[whole + 1] : bytes.size()) <= n)
      ++whole;
    const std::size_t end = whole < starts.size() ? starts[whole] : bytes.size();
    EXPECT_EQ(f.records, whole);
    EXPECT_EQ(f.complete(), end == n);
    if (!f.complete()) {
      EXPECT_EQ(f.problem_offset, end);
      EXPECT_EQ(f.bytes_skipped, n - end);
      EXPECT_EQ(f.damage_count, 1u);
      EXPECT_NE(f.problem.find("the last record, at byte " + std::to_string(end) + ", is cut"),
                std::string::npos)
          << f.problem;
    }
    std::size_t kept = 0;
    for (const MessageSeries& s : f.series) kept += s.size();
    EXPECT_EQ(kept + f.unknown_frames, f.records);
  }
}

TEST(TlogFile, NoiseBetweenRecordsIsSkippedToTheNextRecord) {
  TlogWriter w;
  w.Record(kT0Us, AttitudeFrame(0, 1000, 0.1f, 0.2f));
  const std::size_t noise_at = w.Raw("some noise\xFD\x01");
  // A frame of an unknown message after noise: verified by the record after it.
  const std::size_t next = w.Record(kT0Us + 100'000, UnknownFrame(1));
  w.Record(kT0Us + 200'000, AttitudeFrame(2, 1100, 0.3f, 0.4f));
  const TlogFile f = Parse(w.bytes(), "noisy.tlog");
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, noise_at);
  EXPECT_EQ(f.problem, "12 bytes at byte " + std::to_string(noise_at) +
                           " are no record (its timestamp, 8317987317879828329 microseconds "
                           "since 1970, is no date between 2000 and 2100): skipped to the next "
                           "record, at byte " +
                           std::to_string(next));
  EXPECT_EQ(f.bytes_skipped, 12u);
  EXPECT_EQ(f.damage_count, 1u);
  EXPECT_EQ(f.records, 3u);
  EXPECT_EQ(f.unknown_frames, 1u);
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 2u);
}

TEST(TlogFile, AFrameFailingItsChecksumIsSkipped) {
  TlogWriter w;
  w.Record(kT0Us, AttitudeFrame(0, 1000, 0.1f, 0.2f));
  std::string bad = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  bad[15] = static_cast<char>(bad[15] ^ 0x01);
  const std::size_t bad_at = w.Record(kT0Us + 100'000, bad);
  w.Record(kT0Us + 200'000, AttitudeFrame(2, 1200, 0.5f, 0.6f));
  const TlogFile f = Parse(w.bytes(), "bad.tlog");
  EXPECT_EQ(f.bad_crc, 1u);
  EXPECT_EQ(f.problem_offset, bad_at);
  EXPECT_NE(f.problem.find("its ATTITUDE (id 30) frame from 1:1 fails its checksum"),
            std::string::npos)
      << f.problem;
  EXPECT_EQ(f.bytes_skipped, 8u + bad.size());
  EXPECT_EQ(f.records, 2u);
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 2u);
  EXPECT_EQ(f.sequences.lost(), 1u);
}

TEST(TlogFile, ARecordTimedOutsideTheCenturyIsSkipped) {
  TlogWriter w;
  w.Record(kT0Us, AttitudeFrame(0, 1000, 0.1f, 0.2f));
  const std::string frame = AttitudeFrame(1, 1100, 0.3f, 0.4f);
  const std::size_t at = w.Record(5, frame);
  w.Record(kT0Us + 200'000, AttitudeFrame(2, 1200, 0.5f, 0.6f));
  const TlogFile f = Parse(w.bytes(), "time.tlog");
  EXPECT_EQ(f.problem_offset, at);
  EXPECT_NE(f.problem.find("its timestamp, 5 microseconds since 1970, is no date"),
            std::string::npos)
      << f.problem;
  EXPECT_EQ(f.bytes_skipped, 8u + frame.size());
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 2u);
}

TEST(TlogFile, IncompatibleFramesAndAClockGoingBackAreNoted) {
  TlogWriter w;
  w.Record(kT0Us + 100'000, AttitudeFrame(0, 1000, 0.1f, 0.2f));
  w.Record(kT0Us, AttitudeFrame(1, 1100, 0.3f, 0.4f));
  test_support::FrameSpec spec;
  spec.incompat = 0x04;
  spec.seq = 2;
  spec.payload = test_support::AttitudePayload(1, 1, 1, 1, 1, 1, 1);
  w.Record(kT0Us + 200'000, test_support::EncodeFrame(spec));
  const TlogFile f = Parse(w.bytes(), "odd.tlog");
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.records, 3u);
  EXPECT_EQ(f.incompatible, 1u);
  EXPECT_EQ(f.FrameCount("ATTITUDE"), 2u);
  EXPECT_EQ(f.first_time_us, kT0Us + 100'000);
  ASSERT_EQ(f.notes.size(), 2u);
  EXPECT_NE(f.notes[0].find("1 frames have MAVLink 2 incompat flags"), std::string::npos);
  EXPECT_NE(f.notes[1].find("1 records are timed earlier"), std::string::npos);
}

}  // namespace
}  // namespace odonata::mavlink

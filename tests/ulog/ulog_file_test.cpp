// Reading ULog files: a synthetic log with every message kind reads back exactly; appended data;
// and damage (a cut at every byte, wrong sizes, unknown flags, bad magic) stops the reading at
// the first problem, named with its byte offset, keeping all that came before.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "ulog/ulog_file.hpp"
#include "ulog_writer.hpp"

namespace odonata::ulog {
namespace {

using testing::MotorSample;
using testing::Payload;
using testing::SensorSample;
using testing::UlogWriter;

UlogFile ParseBytes(const std::string& bytes) { return Parse(bytes, "test.ulg"); }

bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::uint64_t RawField(const Subscription& s, std::size_t sample, const char* path) {
  const FieldLayout* f = s.layout->Find(path);
  EXPECT_NE(f, nullptr) << path;
  return f ? ReadUnsignedLE(s.Sample(sample) + f->offset, SizeOf(f->type)) : 0;
}

TEST(UlogFile, EveryMessageKindReadsBackExactly) {
  const UlogWriter w = testing::EveryMessageKindLog();
  const UlogFile f = ParseBytes(w.bytes());
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.source, "test.ulg");
  EXPECT_EQ(f.file_size, w.size());
  EXPECT_EQ(f.version, 1);
  EXPECT_EQ(f.start_time_us, 1'000'000u);
  EXPECT_TRUE(f.flags.present);
  EXPECT_TRUE(f.flags.has_default_parameters());
  EXPECT_FALSE(f.flags.has_appended_data());
  EXPECT_EQ(f.formats.size(), 4u);
  EXPECT_EQ(f.formats.at("sensor").fields.size(), 19u);

  // Information, multi-information (continued), parameters.
  EXPECT_EQ(f.info.at("sys_name").Text(), "PX4");
  EXPECT_EQ(f.info.at("ver_sw_release").Integer(), 0x010402ff);
  EXPECT_EQ(f.info.at("time_ref_utc").Integer(), -3600);
  EXPECT_EQ(f.info.at("offsets").type, "float[3]");
  EXPECT_EQ(f.info.at("offsets").bytes.size(), 12u);
  ASSERT_EQ(f.multi_info.at("perf").size(), 2u);
  EXPECT_EQ(f.multi_info.at("perf")[0].Text(), "abcdefgh");
  EXPECT_EQ(f.multi_info.at("perf")[0].type, "char[8]");
  EXPECT_EQ(f.multi_info.at("perf")[1].Text(), "xy");
  EXPECT_EQ(f.initial_parameters.size(), 2u);
  EXPECT_EQ(f.initial_parameters.at("SYS_AUTOSTART").Integer(), 4001);
  EXPECT_EQ(f.initial_parameters.at("MC_ROLL_P").Number(), 6.5);
  ASSERT_EQ(f.changed_parameters.size(), 1u);
  EXPECT_EQ(f.changed_parameters[0].name, "MC_ROLL_P");
  EXPECT_EQ(f.changed_parameters[0].value.Number(), 7.25);
  EXPECT_EQ(f.changed_parameters[0].time_us, 1'100'700u);  // the latest sample before it
  ASSERT_EQ(f.default_parameters.size(), 1u);
  EXPECT_EQ(f.default_parameters[0].default_types, 3);
  EXPECT_EQ(f.default_parameters[0].value.Number(), 7.0);

  // Subscriptions: a topic in two instances; the second unsubscribed.
  ASSERT_EQ(f.subscriptions.size(), 3u);
  const Subscription& sensor = f.subscriptions[0];
  EXPECT_EQ(sensor.topic, "sensor");
  EXPECT_EQ(sensor.layout->logged_size, testing::kSensorLoggedSize);
  ASSERT_EQ(sensor.size(), 3u);
  EXPECT_EQ(sensor.timestamps_us, (std::vector<std::uint64_t>{1'100'000, 1'200'000, 1'300'000}));
  EXPECT_EQ(sensor.first_appended_sample, 3u);
  for (int k = 0; k < 3; ++k) {
    SCOPED_TRACE(k);
    const std::size_t i = static_cast<std::size_t>(k);
    const FieldLayout& q = *sensor.layout->Find("q");
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("i8")), -100 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("u8")), 200 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("i16")), -30000 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("u16")), 60000 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("i32")), -2000000000 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("u32")), 4000000000.0 + k);
    // 64-bit integers: exact from the bytes; as double, rounded like any conversion.
    EXPECT_EQ(static_cast<std::int64_t>(RawField(sensor, i, "i64")), -9000000000000000000LL + k);
    EXPECT_EQ(RawField(sensor, i, "u64"), 18000000000000000000ULL + static_cast<unsigned>(k));
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("u64")),
              static_cast<double>(18000000000000000000ULL + static_cast<unsigned>(k)));
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("f")), 0.25 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("d")), -1e300 * (k + 1));
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("b")), k % 2);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("c")), 'A');
    const FieldLayout& label = *sensor.layout->Find("label");
    EXPECT_EQ(std::string(reinterpret_cast<const char*>(sensor.Sample(i)) + label.offset, 4),
              "abc" + std::to_string(k));
    for (std::size_t e = 0; e < 4; ++e)
      EXPECT_EQ(sensor.Value(i, q, e), static_cast<float>(e) + 0.5f * static_cast<float>(k));
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("accel.z")), k + 2.0);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("mags[1].x")), 20.0 + k);
    EXPECT_EQ(sensor.Value(i, *sensor.layout->Find("wheels[1].rpm")), 2000 + k);
  }
  const Subscription& m0 = f.subscriptions[1];
  const Subscription& m1 = f.subscriptions[2];
  EXPECT_EQ(m0.topic, "motor");
  EXPECT_EQ(m1.topic, "motor");
  EXPECT_EQ(m0.multi_id, 0);
  EXPECT_EQ(m1.multi_id, 1);
  EXPECT_EQ(m0.layout, m1.layout);  // one layout per format
  EXPECT_FALSE(m0.removed);
  EXPECT_TRUE(m1.removed);
  ASSERT_EQ(m0.size(), 2u);
  ASSERT_EQ(m1.size(), 2u);
  // With or without the trailing padding, a sample keeps the logged bytes only.
  EXPECT_EQ(m0.data.size(), 2 * m0.layout->logged_size);
  EXPECT_EQ(m0.Value(1, *m0.layout->Find("thrust"), 1), 0.5);
  EXPECT_EQ(m1.Value(0, *m1.layout->Find("thrust"), 0), 0.75);
  EXPECT_EQ(f.FindTopic("motor", 1), &m1);
  EXPECT_EQ(f.FindSubscription(1), &m0);
  EXPECT_EQ(f.FindSubscription(9), nullptr);

  // Logging, tagged logging, sync, dropouts, the unknown message.
  ASSERT_EQ(f.log_messages.size(), 2u);
  EXPECT_EQ(f.log_messages[0].level, '6');
  EXPECT_FALSE(f.log_messages[0].tag.has_value());
  EXPECT_EQ(f.log_messages[0].timestamp_us, 1'150'000u);
  EXPECT_EQ(f.log_messages[0].text, "[commander] armed");
  EXPECT_EQ(f.log_messages[1].tag, 7);
  EXPECT_EQ(f.log_messages[1].level, '4');
  EXPECT_EQ(f.log_messages[1].timestamp_us, 1'160'000u);
  EXPECT_EQ(f.log_messages[1].text, "low battery");
  EXPECT_EQ(f.sync_count, 1u);
  ASSERT_EQ(f.dropouts.size(), 2u);
  EXPECT_EQ(f.dropouts[0].duration_ms, 20);
  EXPECT_EQ(f.dropouts[0].time_us, 1'100'700u);
  EXPECT_EQ(f.dropout_total_ms, 50u);
  EXPECT_EQ(f.MessageCount('D'), 7u);
  EXPECT_EQ(f.MessageCount('F'), 4u);
  EXPECT_EQ(f.MessageCount('X'), 1u);
  EXPECT_EQ(f.unknown_message_counts.size(), 1u);
  EXPECT_EQ(f.unknown_message_counts.at('X'), 1u);
  std::size_t total = 0;
  for (const auto& [type, n] : f.message_counts) total += n;
  EXPECT_EQ(total, w.written().size());
  EXPECT_EQ(f.appended_messages, 0u);
  EXPECT_TRUE(f.notes.empty());
}

// Data appended after the log was closed (PX4's hardfault log does this) starts at the offset the
// flag bits give: the log before it may end in a cut message, or in zeros the writer reserved.
TEST(UlogFile, AppendedDataContinuesTheLogAfterACutMessage) {
  for (const bool zeros : {false, true}) {
    SCOPED_TRACE(zeros ? "zero padding before the appended data" : "cut message");
    UlogWriter w(1, 5'000'000);
    w.FlagBits({}, {1, 0, 0, 0, 0, 0, 0, 0})
        .Format(testing::kMotorFormat)
        .Subscribe(0, 0, "motor")
        .Data(0, MotorSample(5'100'000, 1.0f, 2.0f, false))
        .Data(0, MotorSample(5'200'000, 3.0f, 4.0f, false));
    // (A cut message followed by zeros is not told apart from a whole one when its claimed size
    // ends inside the zeros: no reader can, the bytes are the same.)
    if (zeros)
      w.Raw(std::string(37, '\0'));
    else
      w.CutMessage('D', 20, std::string("\0\0\x01\x02", 4));
    const std::size_t appended_at = w.size();
    w.SetAppendedOffset(0, appended_at);
    w.Data(0, MotorSample(5'300'000, 5.0f, 6.0f, true))
        .MultiInfo(false, "char[5] hardfault_plain", "crash");
    const UlogFile f = ParseBytes(w.bytes());
    ASSERT_TRUE(f.complete()) << f.problem;
    EXPECT_TRUE(f.flags.has_appended_data());
    EXPECT_EQ(f.flags.appended_offsets[0], appended_at);
    const Subscription& s = f.subscriptions.at(0);
    ASSERT_EQ(s.size(), 3u);
    EXPECT_EQ(s.first_appended_sample, 2u);
    EXPECT_EQ(s.timestamps_us[2], 5'300'000u);
    EXPECT_EQ(s.Value(2, *s.layout->Find("thrust"), 1), 6.0);
    EXPECT_EQ(f.appended_messages, 2u);
    EXPECT_EQ(f.multi_info.at("hardfault_plain").at(0).Text(), "crash");
    ASSERT_EQ(f.notes.size(), 1u);
    EXPECT_TRUE(
        Contains(f.notes[0], "before the data appended at byte " + std::to_string(appended_at)))
        << f.notes[0];
  }
}

TEST(UlogFile, SeveralAppendedOffsetsAndOneAtTheEnd) {
  UlogWriter w(1);
  w.FlagBits({}, {1, 0, 0, 0, 0, 0, 0, 0})
      .Format(testing::kMotorFormat)
      .Subscribe(0, 0, "motor")
      .Data(0, MotorSample(2'000'000, 1.0f, 2.0f, false));
  const std::size_t first = w.size();
  w.Data(0, MotorSample(2'100'000, 1.0f, 2.0f, false)).CutMessage('M', 300, "xx");
  const std::size_t second = w.size();
  w.Data(0, MotorSample(2'200'000, 1.0f, 2.0f, false));
  w.SetAppendedOffset(0, first).SetAppendedOffset(1, second).SetAppendedOffset(2, w.size());
  const UlogFile f = ParseBytes(w.bytes());
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.subscriptions[0].size(), 3u);
  EXPECT_EQ(f.subscriptions[0].first_appended_sample, 1u);
  EXPECT_EQ(f.appended_messages, 2u);
  // An appended offset past the end: the appended data is missing, which is damage.
  UlogWriter past = w;
  past.SetAppendedOffset(2, w.size() + 10);
  const UlogFile g = ParseBytes(past.bytes());
  EXPECT_FALSE(g.complete());
  EXPECT_EQ(g.problem_offset, w.size());
  EXPECT_TRUE(Contains(g.problem, "past the end")) << g.problem;
  EXPECT_EQ(g.subscriptions[0].size(), 3u);
  // Cut anywhere after the header, a file that promises appended data is incomplete, and says
  // where (the header alone, without the flag bits, is an empty log).
  for (std::size_t cut = 17; cut < w.size(); ++cut) {
    const UlogFile c = ParseBytes(w.bytes().substr(0, cut));
    EXPECT_FALSE(c.complete()) << cut;
    EXPECT_LE(c.problem_offset, cut);
  }
}

TEST(UlogFile, ACutAtEveryByteKeepsWhatCameBeforeIt) {
  const UlogWriter w = testing::EveryMessageKindLog();
  const std::string& bytes = w.bytes();
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const std::string prefix = bytes.substr(0, cut);
    if (cut < 16) {
      EXPECT_THROW(ParseBytes(prefix), UlogError);
      continue;
    }
    const UlogFile f = ParseBytes(prefix);
    std::size_t whole = 0, data = 0;
    bool at_boundary = cut == 16;
    for (const auto& m : w.written()) {
      const std::size_t end =
          (&m + 1 != w.written().data() + w.written().size()) ? (&m + 1)->offset : bytes.size();
      if (end <= cut) {
        ++whole;
        data += m.type == 'D';
      }
      at_boundary = at_boundary || end == cut;
    }
    std::size_t read = 0, samples = 0;
    for (const auto& [type, n] : f.message_counts) read += n;
    for (const auto& s : f.subscriptions) samples += s.size();
    EXPECT_EQ(f.complete(), at_boundary) << f.problem;
    EXPECT_EQ(read, whole);
    EXPECT_EQ(samples, data);
    if (!f.complete()) {
      EXPECT_LT(f.problem_offset, cut);
      EXPECT_TRUE(Contains(f.problem, "at byte " + std::to_string(f.problem_offset))) << f.problem;
    }
  }
}

TEST(UlogFile, WrongSizesStopTheReadingThere) {
  // A message claiming more bytes than are left.
  UlogWriter w = testing::EveryMessageKindLog();
  std::string bytes = w.bytes();
  const auto& last = w.written().back();
  bytes[last.offset] = '\x84';
  bytes[last.offset + 1] = '\x03';  // 900 bytes
  UlogFile f = ParseBytes(bytes);
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, last.offset);
  EXPECT_EQ(f.problem, "message of type 'D' at byte " + std::to_string(last.offset) +
                           " claims 900 bytes, only " +
                           std::to_string(bytes.size() - last.offset - 3) + " left");
  EXPECT_EQ(f.subscriptions[0].size(), 2u);  // the two samples before it
  EXPECT_THROW(ParseStrict(bytes, "test.ulg"), UlogError);
  try {
    ParseStrict(bytes, "flight.ulg");
  } catch (const UlogError& e) {
    EXPECT_EQ(std::string(e.what()), "flight.ulg: " + f.problem);
  }

  // A data message shorter than its format, and one longer: both name the topic.
  UlogWriter shorter(1);
  shorter.Format(testing::kMotorFormat).Subscribe(0, 3, "motor");
  const std::size_t bad_at = shorter.size();
  shorter.Data(3, Payload().Put(std::uint64_t{1}).Put(1.0f));
  f = ParseBytes(shorter.bytes());
  EXPECT_EQ(f.problem_offset, bad_at);
  EXPECT_TRUE(Contains(f.problem,
                       "data of 'motor' (msg_id 3) has 12 bytes, its format needs at "
                       "least 16"))
      << f.problem;
  UlogWriter longer(1);
  longer.Format(testing::kMotorFormat).Subscribe(0, 3, "motor");
  longer.Data(3, MotorSample(1, 1.0f, 1.0f, true).Fill(1));
  f = ParseBytes(longer.bytes());
  EXPECT_TRUE(Contains(f.problem, "has 21 bytes, its format has only 20")) << f.problem;

  // Key lengths beyond the payload; fields beyond it.
  UlogWriter key(1);
  key.Message('I', std::string("\x40int32_t x", 10));
  f = ParseBytes(key.bytes());
  EXPECT_TRUE(Contains(f.problem, "message of type 'I' at byte 16: the key needs 64 bytes"))
      << f.problem;
  UlogWriter logging(1);
  logging.Message('L', "6abc");
  f = ParseBytes(logging.bytes());
  EXPECT_TRUE(Contains(f.problem, "timestamp needs 8 bytes")) << f.problem;
  UlogWriter info(1);
  info.Info("int32_t x", "abc");
  EXPECT_TRUE(Contains(ParseBytes(info.bytes()).problem, "has 3 bytes, its type 4"));
}

TEST(UlogFile, MessagesThatBreakTheRulesAreDamage) {
  const auto problem = [](const UlogWriter& w) { return ParseBytes(w.bytes()).problem; };
  UlogWriter data_without_subscription(1);
  data_without_subscription.Data(4, MotorSample(1, 1, 1, false));
  EXPECT_TRUE(Contains(problem(data_without_subscription), "msg_id 4, which no subscription"));
  UlogWriter no_format(1);
  no_format.Subscribe(0, 0, "motor");
  EXPECT_TRUE(Contains(problem(no_format), "no format message defines 'motor'"));
  UlogWriter no_timestamp(1);
  no_timestamp.Format("m:float x;").Subscribe(0, 0, "m");
  EXPECT_TRUE(Contains(problem(no_timestamp), "uint64_t timestamp"));
  UlogWriter redefined(1);
  redefined.Format("m:uint64_t timestamp;")
      .Format("m:uint64_t timestamp;")
      .Format("m:uint64_t timestamp;float x;");
  EXPECT_TRUE(Contains(problem(redefined), "defined a second time, differently"));
  UlogWriter bad_format(1);
  bad_format.Format("m:uint64_t timestamp;float[x] y;");
  EXPECT_TRUE(Contains(problem(bad_format), "message of type 'F' at byte 16: type 'float[x]'"));
  UlogWriter two_ids(1);
  two_ids.Format(testing::kMotorFormat).Format("n:uint64_t timestamp;").Subscribe(0, 0, "motor");
  two_ids.Subscribe(0, 0, "motor");  // repeated as it was: fine
  two_ids.Subscribe(0, 0, "n");
  EXPECT_TRUE(Contains(problem(two_ids), "msg_id 0 subscribes 'n' but is already 'motor'"));
  UlogWriter late_flags(1);
  late_flags.Format("m:uint64_t timestamp;").FlagBits();
  EXPECT_TRUE(Contains(problem(late_flags), "must be the first message"));
  UlogWriter short_flags(1);
  short_flags.Message('B', std::string(39, '\0'));
  EXPECT_TRUE(Contains(problem(short_flags), "has 39 bytes, it needs 40"));
  UlogWriter bad_sync(1);
  bad_sync.Message('S', "12345678");
  EXPECT_TRUE(Contains(problem(bad_sync), "sync magic"));
  UlogWriter text_parameter(1);
  text_parameter.Parameter("char[2] P", "ab");
  EXPECT_TRUE(Contains(problem(text_parameter), "parameters are numbers"));
  UlogWriter type_zero(1);
  type_zero.Message('\0', "abc").Data(0, Payload());
  EXPECT_TRUE(Contains(problem(type_zero), "type 0"));
  UlogWriter inside(1);
  inside.FlagBits({}, {1, 0, 0, 0, 0, 0, 0, 0}, {30, 0, 0});
  EXPECT_TRUE(Contains(problem(inside), "appended data is placed at byte 30"));
}

TEST(UlogFile, FlagBitsAreCheckedAsTheSpecSays) {
  // An unknown incompatible bit: the log must be refused; what came before (the header) stays.
  UlogWriter incompat(1, 77);
  incompat.FlagBits({}, {0, 0, 0, 0, 0, 0, 0, 0x10}).Format(testing::kMotorFormat);
  UlogFile f = ParseBytes(incompat.bytes());
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, 16u);
  EXPECT_TRUE(Contains(f.problem, "unknown incompatible flag bits")) << f.problem;
  EXPECT_TRUE(Contains(f.problem, "0000000000000010")) << f.problem;
  EXPECT_EQ(f.start_time_us, 77u);
  EXPECT_TRUE(f.formats.empty());
  UlogWriter bit1(1);
  bit1.FlagBits({}, {2, 0, 0, 0, 0, 0, 0, 0});
  EXPECT_FALSE(ParseBytes(bit1.bytes()).complete());

  // Unknown compatible bits, a longer flag bits message, a later version: read, with notes.
  UlogWriter compat(7);
  compat.FlagBits({0, 4, 0, 0, 0, 0, 0, 0}, {}, {}, 8).Format(testing::kMotorFormat);
  f = ParseBytes(compat.bytes());
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.version, 7);
  EXPECT_EQ(f.formats.size(), 1u);
  EXPECT_EQ(f.notes.size(), 3u);

  // Offsets without the data-appended bit are not used.
  UlogWriter unflagged(1);
  unflagged.FlagBits({}, {}, {5000, 0, 0}).Format(testing::kMotorFormat);
  f = ParseBytes(unflagged.bytes());
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.appended_messages, 0u);
}

TEST(UlogFile, ZeroPaddingAtTheEndIsNoDamage) {
  UlogWriter w = testing::EveryMessageKindLog();
  w.Raw(std::string(100, '\0'));
  const UlogFile f = ParseBytes(w.bytes());
  EXPECT_TRUE(f.complete()) << f.problem;
  ASSERT_EQ(f.notes.size(), 1u);
  EXPECT_TRUE(Contains(f.notes[0], "100 zero bytes")) << f.notes[0];
  // Zeros followed by anything else are not padding.
  w.Raw("x");
  EXPECT_FALSE(ParseBytes(w.bytes()).complete());
}

TEST(UlogFile, WhatIsNoULogThrows) {
  EXPECT_THROW(ParseBytes(""), UlogError);
  EXPECT_THROW(ParseBytes("ULog\x01\x12"), UlogError);  // cut inside the header
  try {
    ParseBytes("PK\x03\x04 this is a zip archive, not a flight log");
    ADD_FAILURE() << "no throw";
  } catch (const UlogError& e) {
    EXPECT_TRUE(Contains(e.what(), "test.ulg: not a ULog file")) << e.what();
  }
  std::string wrong = testing::EveryMessageKindLog().bytes();
  wrong[6] = 0x36;
  EXPECT_THROW(ParseBytes(wrong), UlogError);
  EXPECT_THROW(Read("/nonexistent/flight.ulg"), UlogError);
  // Just the header: a log with nothing in it, complete.
  const UlogFile f = ParseBytes(UlogWriter(1, 42).bytes());
  EXPECT_TRUE(f.complete());
  EXPECT_EQ(f.start_time_us, 42u);
  EXPECT_FALSE(f.flags.present);
}

TEST(UlogFile, ReadsFromAPathAndAsBytes) {
  const std::string bytes = testing::EveryMessageKindLog().bytes();
  const std::string path = ::testing::TempDir() + "ulog_file_test.ulg";
  {
    std::ofstream out(path, std::ios::binary);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  }
  const UlogFile f = ReadStrict(path);
  EXPECT_EQ(f.source, path);
  EXPECT_EQ(f.subscriptions[0].size(), 3u);
  const std::vector<std::uint8_t> v(bytes.begin(), bytes.end());
  EXPECT_EQ(Parse(v, "v").subscriptions[0].data, f.subscriptions[0].data);
  std::remove(path.c_str());
}

}  // namespace
}  // namespace odonata::ulog

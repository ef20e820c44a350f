// Reading Crazyflie micro-SD logs: synthetic logs (usd_log_writer.hpp) with every struct code, both
// versions, the fixed-frequency block, half floats, good and bad CRCs read back exactly; damage (a
// cut at every byte, every byte flipped, an undeclared type id, a header cut short or declaring
// too much) stops the reading at the first problem, named with its byte offset, keeping all that
// came before. The real logs: usd_log_real_files_test.cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "usd_log_test_support.hpp"
#include "usd_log_writer.hpp"

namespace odonata::crazyflie_usd {
namespace {

using testing::Contains;
using testing::ExpectRecordsOf;

using testing::BitwiseCrc32;
using testing::Packed;
using testing::PutLE;
using testing::UsdLogWriter;

std::string ParseError(const std::string& bytes) {
  try {
    (void)Parse(bytes, "bad.log");
  } catch (const UsdLogError& e) {
    return e.what();
  }
  return "(no error)";
}

// Four event types: every struct code, the fixed-frequency block, a payload with half floats
// (1, the smallest subnormal, -inf) and a type without variables.
UsdLogWriter EveryCodeLog(std::uint16_t version = 2) {
  UsdLogWriter w(version, {{3, "estGyroscope", {"gyro.x(f)", "gyro.y(f)", "gyro.z(f)"}},
                           {kFixedFrequencyId,
                            "fixedFrequency",
                            {"motor.m1(H)", "ctrl.flag(B)", "ctrl.mode(b)", "ctrl.rate(h)",
                             "ctrl.count(I)", "ctrl.sum(i)"}},
                           {12, "estTDOA", {"idA(B)", "idB(B)", "distanceDiff(e)"}},
                           {7, "estAbsoluteHeight", {}}});
  const std::int32_t int_min = std::numeric_limits<std::int32_t>::min();
  w.Record(3, 1000000, Packed().F32(0.5f).F32(-1.25f).F32(3.0e-3f));
  w.Record(kFixedFrequencyId, 1000500,
           Packed().U16(65535).U8(255).I8(-128).I16(-32768).U32(4294967295u).I32(int_min));
  w.Record(12, 1001000, Packed().U8(1).U8(2).Half(0x3c00));
  w.Record(7, 1001500);
  w.Record(3, 1002000, Packed().F32(0.75f).F32(0.0f).F32(-2.0f));
  w.Record(12, 1002500, Packed().U8(3).U8(4).Half(0x0001));
  w.Record(kFixedFrequencyId, 1003000,
           Packed().U16(0).U8(0).I8(127).I16(32767).U32(0).I32(2147483647));
  w.Record(12, 1003500, Packed().U8(5).U8(6).Half(0xfc00));
  return w;
}

TEST(UsdLogFile, EveryCodeReadsBackExactly) {
  const UsdLogWriter w = EveryCodeLog();
  const std::string bytes = w.Finish();
  const UsdLogFile f = Parse(bytes, "test.log");
  ASSERT_TRUE(f.intact()) << f.problem;
  EXPECT_EQ(f.source, "test.log");
  EXPECT_EQ(f.file_size, bytes.size());
  EXPECT_EQ(f.version, 2);
  EXPECT_EQ(f.header_size, w.header_size());
  EXPECT_EQ(f.records, 8u);
  EXPECT_TRUE(f.notes.empty());
  EXPECT_EQ(f.crc_stored, BitwiseCrc32(bytes.substr(0, bytes.size() - 4)));
  ASSERT_EQ(f.event_types.size(), 4u);

  const EventType& gyro = f.event_types[0];
  EXPECT_EQ(gyro.id, 3);
  EXPECT_EQ(gyro.name, "estGyroscope");
  EXPECT_FALSE(gyro.fixed_frequency());
  ASSERT_EQ(gyro.variables.size(), 3u);
  EXPECT_EQ(gyro.variables[1].name, "gyro.y");
  EXPECT_EQ(gyro.variables[1].code, 'f');
  EXPECT_EQ(gyro.record_size, 12u);
  EXPECT_EQ(gyro.time_us, (std::vector<std::uint64_t>{1000000, 1002000}));
  EXPECT_EQ(gyro.Value(0, 0), 0.5);
  EXPECT_EQ(gyro.Value(0, 1), -1.25);
  EXPECT_EQ(gyro.Value(0, 2), static_cast<double>(3.0e-3f));
  EXPECT_EQ(gyro.Value(1, 2), -2.0);

  const EventType& fixed = f.event_types[1];
  EXPECT_TRUE(fixed.fixed_frequency());
  EXPECT_EQ(fixed.record_size, 2u + 1 + 1 + 2 + 4 + 4);
  const std::vector<double> extremes = {65535, 255, -128, -32768, 4294967295.0, -2147483648.0};
  const std::vector<double> others = {0, 0, 127, 32767, 0, 2147483647};
  ASSERT_EQ(fixed.size(), 2u);
  for (std::size_t j = 0; j < extremes.size(); ++j) {
    EXPECT_EQ(fixed.Value(0, j), extremes[j]) << j;
    EXPECT_EQ(fixed.Value(1, j), others[j]) << j;
  }

  const EventType& tdoa = f.event_types[2];
  EXPECT_EQ(tdoa.variables[2].name, "distanceDiff");
  EXPECT_EQ(tdoa.variables[2].code, 'e');
  EXPECT_EQ(tdoa.record_size, 4u);
  ASSERT_EQ(tdoa.size(), 3u);
  EXPECT_EQ(tdoa.Value(0, 2), 1.0);
  EXPECT_EQ(tdoa.Value(1, 2), std::ldexp(1.0, -24));
  EXPECT_EQ(tdoa.Value(2, 2), -std::numeric_limits<double>::infinity());
  EXPECT_EQ(tdoa.Value(2, 1), 6.0);

  const EventType& height = f.event_types[3];
  EXPECT_TRUE(height.variables.empty());
  EXPECT_EQ(height.size(), 1u);
  EXPECT_TRUE(height.values.empty());

  EXPECT_EQ(f.RecordCount(3), 2u);
  EXPECT_EQ(f.RecordCount(kFixedFrequencyId), 2u);
  EXPECT_EQ(f.RecordCount(12), 3u);
  EXPECT_EQ(f.RecordCount(7), 1u);
  EXPECT_EQ(f.RecordCount(99), 0u);
  EXPECT_EQ(f.FindType("estTDOA"), &f.event_types[2]);
  EXPECT_EQ(f.FindType(std::string_view("estPose")), nullptr);
}

TEST(UsdLogFile, Version1TimestampsAreMilliseconds) {
  UsdLogWriter w(1, {{2, "estAcceleration", {"acc.x(f)"}}, {1, "estBarometer", {"baro.asl(f)"}}});
  w.Record(2, 1500, Packed().F32(1.0f));
  w.Record(1, 4294967295u, Packed().F32(-2.0f));
  const UsdLogFile f = Parse(w.Finish(), "v1.log");
  ASSERT_TRUE(f.intact()) << f.problem;
  EXPECT_EQ(f.version, 1);
  EXPECT_EQ(f.file_size, w.header_size() + 2 * (2 + 4 + 4) + 4);
  EXPECT_EQ(f.event_types[0].time_us, (std::vector<std::uint64_t>{1500000}));
  EXPECT_EQ(f.event_types[1].time_us, (std::vector<std::uint64_t>{4294967295000u}));
  EXPECT_EQ(f.event_types[1].Value(0, 0), -2.0);
}

TEST(UsdLogFile, HalfFloatsDecodeAsIeeeBinary16) {
  EXPECT_EQ(HalfToDouble(0x3c00), 1.0);
  EXPECT_EQ(HalfToDouble(0xc000), -2.0);
  EXPECT_EQ(HalfToDouble(0x3555), 0.333251953125);
  EXPECT_EQ(HalfToDouble(0x7bff), 65504.0);                  // the largest
  EXPECT_EQ(HalfToDouble(0x0400), std::ldexp(1.0, -14));     // the smallest normal
  EXPECT_EQ(HalfToDouble(0x0001), std::ldexp(1.0, -24));     // the smallest subnormal
  EXPECT_EQ(HalfToDouble(0x03ff), std::ldexp(1023.0, -24));  // the largest subnormal
  EXPECT_EQ(HalfToDouble(0x8001), -std::ldexp(1.0, -24));
  EXPECT_EQ(HalfToDouble(0x0000), 0.0);
  EXPECT_TRUE(std::signbit(HalfToDouble(0x8000)));
  EXPECT_EQ(HalfToDouble(0x7c00), std::numeric_limits<double>::infinity());
  EXPECT_EQ(HalfToDouble(0xfc00), -std::numeric_limits<double>::infinity());
  EXPECT_TRUE(std::isnan(HalfToDouble(0x7e00)));
  EXPECT_TRUE(std::isnan(HalfToDouble(0xfc01)));
}

TEST(UsdLogFile, Crc32IsZlibs) {
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  EXPECT_EQ(Crc32(""), 0u);
  const std::string bytes = EveryCodeLog().Finish();
  EXPECT_EQ(Crc32(bytes), BitwiseCrc32(bytes));
}

TEST(UsdLogFile, ABadCrcIsSaidAndTheRecordsStillRead) {
  const UsdLogWriter w = EveryCodeLog();
  const std::uint32_t good = BitwiseCrc32(w.Finish().substr(0, w.size()));
  const UsdLogFile f = Parse(w.FinishWithCrc(good ^ 1u), "bad-crc.log");
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_FALSE(f.crc_valid);
  EXPECT_FALSE(f.intact());
  EXPECT_EQ(f.crc_stored, good ^ 1u);
  EXPECT_EQ(f.crc_computed, good);
  EXPECT_EQ(f.records, 8u);
  ASSERT_EQ(f.notes.size(), 1u);
  EXPECT_TRUE(Contains(f.notes[0], "CRC32")) << f.notes[0];
  EXPECT_TRUE(Contains(f.notes[0], "read as they are")) << f.notes[0];

  // A value changed after writing: read as it now is, and said.
  std::string changed = w.Finish();
  // gyro.x's last byte holds the sign bit: 0.5 is 0x3f000000.
  char& top = changed[w.starts()[0] + 10 + 3];
  top = static_cast<char>(top ^ '\x80');
  const UsdLogFile g = Parse(changed, "changed.log");
  EXPECT_TRUE(g.complete()) << g.problem;
  EXPECT_FALSE(g.crc_valid);
  EXPECT_EQ(g.event_types[0].Value(0, 0), -0.5);
}

TEST(UsdLogFile, AnUndeclaredTypeIdStopsTheReadingThere) {
  UsdLogWriter w = EveryCodeLog();
  w.Record(99, 1004000, Packed().U32(7));
  w.Record(3, 1005000, Packed().F32(1).F32(2).F32(3));
  const UsdLogFile f = Parse(w.Finish(), "unknown-id.log");
  EXPECT_FALSE(f.complete());
  EXPECT_TRUE(f.crc_valid);  // the bytes are as written: the type was never declared
  EXPECT_EQ(f.problem_offset, w.starts()[8]);
  EXPECT_TRUE(Contains(f.problem, "type id 99")) << f.problem;
  EXPECT_TRUE(Contains(f.problem, "at byte " + std::to_string(w.starts()[8]))) << f.problem;
  EXPECT_TRUE(Contains(f.problem, "not read (8 records before them are)")) << f.problem;
  EXPECT_EQ(f.records, 8u);
  EXPECT_EQ(f.RecordCount(3), 2u);
}

TEST(UsdLogFile, ALogWithoutItsTrailerEndsInACutRecord) {
  // The Crazyflie lost power: no CRC was written, and the last record's bytes look like it.
  const UsdLogWriter w = EveryCodeLog();
  const UsdLogFile f = Parse(w.Finish().substr(0, w.size()), "power-loss.log");
  EXPECT_FALSE(f.complete());
  EXPECT_FALSE(f.crc_valid);
  EXPECT_EQ(f.records, 7u);
  EXPECT_EQ(f.problem_offset, w.starts()[7]);
  EXPECT_TRUE(Contains(f.problem, "record of 'estTDOA' (id 12) at byte " +
                                      std::to_string(w.starts()[7]) + " is cut"))
      << f.problem;
  EXPECT_TRUE(Contains(f.problem, "power loss")) << f.problem;
}

void ExpectACutAtEveryByteKeepsWhatCameBeforeIt(const UsdLogWriter& w) {
  const std::string bytes = w.Finish();
  const UsdLogFile whole = Parse(bytes, "whole.log");
  ASSERT_TRUE(whole.intact()) << whole.problem;
  for (std::size_t cut = 0; cut < bytes.size(); ++cut) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    const std::string prefix = bytes.substr(0, cut);
    if (cut < 5) {
      EXPECT_FALSE(LooksLikeUsdLog(prefix));
      EXPECT_THROW((void)Parse(prefix, "cut.log"), UsdLogError);
      continue;
    }
    const UsdLogFile f = Parse(prefix, "cut.log");
    EXPECT_FALSE(f.intact());
    // The last 4 bytes are taken for the trailer: the records that end before them are read.
    std::size_t whole_records = 0;
    if (cut >= w.header_size() + 4)
      for (const std::size_t end : w.ends()) whole_records += end <= cut - 4 ? 1 : 0;
    EXPECT_EQ(f.records, whole_records);
    ExpectRecordsOf(f, whole);
    if (!f.complete()) {
      EXPECT_LE(f.problem_offset, cut);  // a field cut with nothing of it left starts at the cut
      EXPECT_TRUE(Contains(f.problem, "at byte " + std::to_string(f.problem_offset))) << f.problem;
    }
    if (cut < w.header_size()) {
      EXPECT_FALSE(f.complete());
      EXPECT_EQ(f.header_size, 0u);
      EXPECT_LT(f.event_types.size(), whole.event_types.size());
    }
  }
}

TEST(UsdLogFile, ACutAtEveryByteKeepsWhatCameBeforeIt) {
  ExpectACutAtEveryByteKeepsWhatCameBeforeIt(EveryCodeLog(2));
  ExpectACutAtEveryByteKeepsWhatCameBeforeIt(EveryCodeLog(1));
}

TEST(UsdLogFile, AFlippedByteIsAClearErrorOrAReadThatSaysSo) {
  const std::string bytes = EveryCodeLog().Finish();
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    SCOPED_TRACE("byte " + std::to_string(i) + " flipped");
    std::string b = bytes;
    b[i] = static_cast<char>(b[i] ^ '\xff');
    if (!LooksLikeUsdLog(b)) {
      EXPECT_LT(i, 5u);
      EXPECT_THROW((void)Parse(b, "flipped.log"), UsdLogError);
      continue;
    }
    const UsdLogFile f = Parse(b, "flipped.log");
    EXPECT_FALSE(f.intact());
    if (f.complete()) {
      EXPECT_FALSE(f.notes.empty());
    } else {
      EXPECT_LT(f.problem_offset, b.size());
    }
  }
}

TEST(UsdLogFile, AHeaderCutShortKeepsTheTypesDeclaredWhole) {
  const UsdLogWriter w = EveryCodeLog();
  // Inside the last type's name: its NUL is gone.
  const UsdLogFile f = Parse(w.Finish().substr(0, w.header_size() - 3), "short.log");
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.event_types.size(), 3u);
  EXPECT_EQ(f.header_size, 0u);
  EXPECT_EQ(f.records, 0u);
  EXPECT_FALSE(f.crc_valid);
  EXPECT_TRUE(Contains(f.problem, "the header is cut")) << f.problem;
  EXPECT_TRUE(Contains(f.problem, "3 of the 4 event types")) << f.problem;

  // The header whole, then 3 bytes: no room for the trailer.
  const UsdLogFile g = Parse(w.Finish().substr(0, w.header_size() + 3), "short.log");
  EXPECT_EQ(g.header_size, w.header_size());
  EXPECT_EQ(g.problem_offset, w.header_size());
  EXPECT_TRUE(Contains(g.problem, "without room for the 4-byte CRC trailer")) << g.problem;
}

// A header of one event type: id 3, `name`, then `count` and the `declarations` as given.
std::string OneTypeHeader(const std::string& name, std::uint16_t count,
                          const std::vector<std::string>& declarations) {
  std::string b = "\xbc";
  PutLE(b, 2, 2);
  PutLE(b, 1, 2);
  PutLE(b, 3, 2);
  b += name;
  b += '\0';
  PutLE(b, count, 2);
  for (const std::string& d : declarations) {
    b += d;
    b += '\0';
  }
  PutLE(b, BitwiseCrc32(b), 4);
  return b;
}

TEST(UsdLogFile, DeclarationsItCannotReadAreSaidWhereTheyAre) {
  const auto problem = [](const std::string& bytes) {
    const UsdLogFile f = Parse(bytes, "header.log");
    EXPECT_FALSE(f.complete());
    EXPECT_TRUE(f.event_types.empty());
    EXPECT_TRUE(Contains(f.problem, "at byte " + std::to_string(f.problem_offset))) << f.problem;
    return f.problem;
  };
  EXPECT_TRUE(Contains(problem(OneTypeHeader("estGyroscope", 1, {"gyro.x(d)"})),
                       "has type code 'd'; the format's codes are B b H h I i f e"));
  EXPECT_TRUE(Contains(problem(OneTypeHeader("estGyroscope", 1, {"gyro.x"})), "not 'name(T)'"));
  EXPECT_TRUE(Contains(problem(OneTypeHeader("estGyroscope", 1, {"(f)"})), "not 'name(T)'"));
  EXPECT_TRUE(Contains(problem(OneTypeHeader("", 0, {})), "has no name"));
  EXPECT_TRUE(Contains(problem(OneTypeHeader(std::string(300, 'a'), 0, {})),
                       "this reader refuses over 255"));
  // An absurd count is refused before anything is made of it.
  const std::string many = OneTypeHeader("estGyroscope", 60000, {"gyro.x(f)"});
  EXPECT_TRUE(Contains(problem(many), "declares 60000 variables at byte 20")) << problem(many);

  UsdLogWriter twice(2, {{3, "estGyroscope", {"gyro.x(f)"}}, {3, "estAcceleration", {}}});
  const UsdLogFile f = Parse(twice.Finish(), "twice.log");
  EXPECT_EQ(f.event_types.size(), 1u);
  EXPECT_TRUE(Contains(f.problem, "takes an id already declared by 'estGyroscope'")) << f.problem;
}

TEST(UsdLogFile, WhatIsNoMicroSdLogThrowsAndIsNotTakenForOne) {
  std::string start = "\xbc";
  PutLE(start, 2, 2);
  PutLE(start, 4, 2);
  EXPECT_TRUE(LooksLikeUsdLog(start));
  EXPECT_TRUE(LooksLikeUsdLog(EveryCodeLog().Finish()));
  EXPECT_FALSE(LooksLikeUsdLog(start.substr(0, 4)));
  EXPECT_TRUE(Contains(ParseError(""), "empty"));
  EXPECT_TRUE(Contains(ParseError("ULog\x01\x12\x35"), "not a Crazyflie micro-SD log"));
  EXPECT_FALSE(LooksLikeUsdLog("ULog\x01\x12\x35"));
  EXPECT_TRUE(Contains(ParseError(start.substr(0, 3)), "only 3 bytes"));
  for (const std::uint16_t version : {0, 3, 0x0200}) {
    std::string b = "\xbc";
    PutLE(b, version, 2);
    PutLE(b, 1, 2);
    EXPECT_FALSE(LooksLikeUsdLog(b));
    EXPECT_TRUE(Contains(ParseError(b), "version " + std::to_string(version))) << ParseError(b);
  }
  std::string most = "\xbc";
  PutLE(most, 1, 2);
  PutLE(most, kMaxEventTypes, 2);
  EXPECT_TRUE(LooksLikeUsdLog(most));
  std::string too_many = "\xbc";
  PutLE(too_many, 2, 2);
  PutLE(too_many, 5000, 2);
  EXPECT_FALSE(LooksLikeUsdLog(too_many));
  EXPECT_TRUE(Contains(ParseError(too_many), "declares 5000 event types")) << ParseError(too_many);

  // No event type at all: an empty log, whole.
  const UsdLogFile empty = Parse(UsdLogWriter(2, {}).Finish(), "empty.log");
  EXPECT_TRUE(empty.intact()) << empty.problem;
  EXPECT_EQ(empty.header_size, 5u);
  EXPECT_TRUE(empty.event_types.empty());
}

TEST(UsdLogFile, ReadReadsAFileAndThrowsWhenItCannot) {
  const std::string bytes = EveryCodeLog().Finish();
  const std::string path = ::testing::TempDir() + "usd_log_test_log00";
  std::ofstream(path, std::ios::binary) << bytes;
  const UsdLogFile f = Read(path);
  EXPECT_TRUE(f.intact()) << f.problem;
  EXPECT_EQ(f.source, path);
  ExpectRecordsOf(f, Parse(bytes, "same"));
  EXPECT_THROW((void)Read(path + ".missing"), UsdLogError);
  EXPECT_THROW((void)Read(::testing::TempDir()), UsdLogError);
}

}  // namespace
}  // namespace odonata::crazyflie_usd

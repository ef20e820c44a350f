// Reading DataFlash logs: a synthetic log reads back exactly (formats, records in place, counts),
// and damage (a cut at every byte, bytes between records, a record of a type without FMT, FMT
// records that cannot hold) is reported with its byte offset, every whole record kept.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"
#include "dataflash_writer.hpp"

namespace odonata::dataflash {
namespace {

using testing::DataflashWriter;

bool Holds(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

std::size_t AllRecords(const DataflashFile& f) {
  std::size_t n = 0;
  for (const auto& [type, count] : f.record_counts) n += count;
  return n;
}

// Where FlightLog()'s records start, and its end: the cuts that leave whole records only.
const std::vector<std::size_t> kFlightBoundaries = {0,   89,  178, 267, 356, 373,
                                                    386, 403, 478, 495, 508};

TEST(DataflashFile, FlightLogReadsBackExactly) {
  const DataflashWriter w = testing::FlightLog();
  const DataflashFile f = Parse(w.bytes(), "flight.bin");
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.source, "flight.bin");
  EXPECT_EQ(f.file_size, 508u);
  EXPECT_EQ(f.bytes, w.bytes());
  EXPECT_EQ(f.bytes_skipped, 0u);
  EXPECT_EQ(f.damage_count, 0u);
  EXPECT_TRUE(f.notes.empty());
  EXPECT_TRUE(f.unknown_type_counts.empty());

  ASSERT_EQ(f.formats.size(), 4u);
  const MessageFormat* att = f.FindFormat("ATT");
  ASSERT_NE(att, nullptr);
  EXPECT_EQ(att->type, 129);
  EXPECT_EQ(att->name, "ATT");
  EXPECT_EQ(att->length, 17u);
  EXPECT_EQ(att->payload_size(), 14u);
  EXPECT_EQ(att->format, "QccC");
  EXPECT_EQ(att->labels, (std::vector<std::string>{"TimeUS", "Roll", "Pitch", "Yaw"}));
  EXPECT_TRUE(att->decodable());
  EXPECT_EQ(att->defined_at, 89u);
  ASSERT_EQ(att->fields.size(), 4u);
  EXPECT_EQ(att->fields[2].label, "Pitch");
  EXPECT_EQ(att->fields[2].type, 'c');
  EXPECT_EQ(att->fields[2].offset, 10u);
  EXPECT_EQ(att->fields[3].offset, 12u);
  EXPECT_EQ(att->IndexOf("Yaw"), 3u);
  EXPECT_FALSE(att->IndexOf("Roll2").has_value());

  EXPECT_EQ(f.messages.at("FMT").offsets, (std::vector<std::uint64_t>{0, 89, 178, 267}));
  EXPECT_EQ(f.messages.at("ATT").offsets, (std::vector<std::uint64_t>{356, 386, 478}));
  EXPECT_EQ(f.messages.at("MODE").offsets, (std::vector<std::uint64_t>{373, 495}));
  EXPECT_EQ(f.RecordCount("MSG"), 1u);
  EXPECT_EQ(f.RecordCount("XYZ"), 0u);
  EXPECT_EQ(f.FindMessage("XYZ"), nullptr);
  EXPECT_EQ(f.FindFormat("XYZ"), nullptr);
  EXPECT_EQ(f.record_counts.at(128), 4u);
  EXPECT_EQ(f.record_counts.at(129), 3u);
  EXPECT_EQ(f.record_counts.at(130), 2u);
  EXPECT_EQ(f.record_counts.at(131), 1u);

  // Fields read in place, unscaled: ATT's second record, MSG's text.
  const std::uint8_t* p = f.Payload(f.messages.at("ATT").offsets[1]);
  EXPECT_EQ(RawValue(p, att->fields[0]), 1100000.0);
  EXPECT_EQ(RawValue(p, att->fields[1]), 160.0);
  EXPECT_EQ(RawValue(p, att->fields[2]), -240.0);
  EXPECT_EQ(RawValue(p, att->fields[3]), 1.0);
  const MessageFormat* msg = f.FindFormat("MSG");
  ASSERT_NE(msg, nullptr);
  EXPECT_EQ(FieldText(f.Payload(f.messages.at("MSG").offsets[0]), msg->fields[1]), "hello");
}

TEST(DataflashFile, EveryFormatCharacterHasItsSize) {
  const std::string chars = "abBhHiIfdnNZcCeELMqQ";
  const std::vector<std::size_t> sizes = {64, 1,  1, 2, 2, 4, 4, 4, 8, 4,
                                          16, 64, 2, 2, 4, 4, 4, 1, 8, 8};
  for (std::size_t i = 0; i < chars.size(); ++i) {
    SCOPED_TRACE(chars[i]);
    ASSERT_TRUE(LookupFormatChar(chars[i]).has_value());
    EXPECT_EQ(LookupFormatChar(chars[i])->size, sizes[i]);
  }
  EXPECT_DOUBLE_EQ(LookupFormatChar('c')->scale, 0.01);
  EXPECT_DOUBLE_EQ(LookupFormatChar('E')->scale, 0.01);
  EXPECT_DOUBLE_EQ(LookupFormatChar('L')->scale, 1e-7);
  EXPECT_EQ(LookupFormatChar('f')->scale, 1.0);
  EXPECT_FALSE(LookupFormatChar('x').has_value());
  EXPECT_FALSE(LookupFormatChar('\0').has_value());
  EXPECT_EQ(DataflashWriter::PayloadSize(chars), 207u);
}

TEST(DataflashFile, ReadsAFileOnDisk) {
  const std::string path = ::testing::TempDir() + "dataflash_test_flight.bin";
  const DataflashWriter w = testing::FlightLog();
  {
    std::ofstream out(path, std::ios::binary);
    out.write(w.bytes().data(), static_cast<std::streamsize>(w.size()));
  }
  const DataflashFile f = Read(path);
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.source, path);
  EXPECT_EQ(f.file_size, w.size());
  EXPECT_EQ(f.RecordCount("ATT"), 3u);
  EXPECT_THROW(Read(::testing::TempDir() + "no_such_dir/none.bin"), DataflashError);
}

TEST(DataflashFile, TellsADataflashLogByItsContent) {
  const std::string log = testing::FlightLog().bytes();
  EXPECT_TRUE(LooksLikeDataflash(log));
  EXPECT_TRUE(LooksLikeDataflash(std::string("\xA3\x95\x80", 3)));
  EXPECT_FALSE(LooksLikeDataflash(std::string("\xA3\x95", 2)));
  EXPECT_FALSE(LooksLikeDataflash(std::string("\xA3\x95\x81", 3)));  // opens with no FMT
  EXPECT_FALSE(LooksLikeDataflash("ULog\x01\x12\x35"));
  EXPECT_FALSE(LooksLikeDataflash(""));

  EXPECT_THROW(Parse("", "empty.bin"), DataflashError);
  EXPECT_THROW(Parse(std::string("\xA3\x95\x81", 3) + log.substr(3), "x.bin"), DataflashError);
  try {
    Parse("ULog\x01\x12\x35 and more", "px4.ulg");
    ADD_FAILURE() << "a ULog file parsed as DataFlash";
  } catch (const DataflashError& e) {
    EXPECT_TRUE(Holds(e.what(), "px4.ulg: not an ArduPilot DataFlash log")) << e.what();
  }
}

TEST(DataflashFile, EveryCutKeepsTheWholeRecordsBeforeIt) {
  const std::string bytes = testing::FlightLog().bytes();
  ASSERT_EQ(bytes.size(), kFlightBoundaries.back());
  for (std::size_t n = 0; n <= bytes.size(); ++n) {
    SCOPED_TRACE(n);
    const std::string cut = bytes.substr(0, n);
    if (n < kRecordHeaderSize) {
      EXPECT_THROW(Parse(cut, "cut.bin"), DataflashError);
      continue;
    }
    const DataflashFile f = Parse(cut, "cut.bin");
    const auto last =
        std::prev(std::upper_bound(kFlightBoundaries.begin(), kFlightBoundaries.end(), n));
    EXPECT_EQ(AllRecords(f), static_cast<std::size_t>(last - kFlightBoundaries.begin()));
    if (*last == n) {
      EXPECT_TRUE(f.complete()) << f.problem;
      EXPECT_EQ(f.bytes_skipped, 0u);
    } else {
      EXPECT_FALSE(f.complete());
      EXPECT_EQ(f.problem_offset, *last);
      EXPECT_EQ(f.bytes_skipped, n - *last);
      EXPECT_EQ(f.damage_count, 1u);
      EXPECT_TRUE(Holds(f.problem, "is cut")) << f.problem;
    }
    for (const SignalInfo& s : ListSignals(f))
      EXPECT_EQ(Extract(f, s.name).values.size(), s.samples) << s.name;
  }
}

TEST(DataflashFile, ResynchronisesAfterBytesBetweenRecords) {
  const DataflashFile f = Parse(testing::FlightLog("garbage").bytes(), "garbage.bin");
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, 373u);
  EXPECT_TRUE(Holds(f.problem, "7 bytes at byte 373 are no record")) << f.problem;
  EXPECT_TRUE(Holds(f.problem, "the next record header, at byte 380")) << f.problem;
  EXPECT_EQ(f.bytes_skipped, 7u);
  EXPECT_EQ(f.damage_count, 1u);
  EXPECT_EQ(f.messages.at("ATT").offsets, (std::vector<std::uint64_t>{356, 393, 485}));
  EXPECT_EQ(f.RecordCount("MODE"), 2u);
  EXPECT_EQ(f.RecordCount("MSG"), 1u);
  EXPECT_EQ(Extract(f, "ATT.Roll").values.size(), 3u);
}

TEST(DataflashFile, SkipsARecordOfATypeWithoutFmt) {
  const std::string unknown = std::string{'\xA3', '\x95', '\x4d'} + "0123456789";
  const DataflashFile f = Parse(testing::FlightLog(unknown).bytes(), "unknown.bin");
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, 373u);
  EXPECT_TRUE(Holds(f.problem, "a record of type 77 at byte 373 has no FMT")) << f.problem;
  EXPECT_EQ(f.unknown_type_counts.at(77), 1u);
  EXPECT_EQ(f.bytes_skipped, 13u);
  EXPECT_EQ(f.damage_count, 1u);
  EXPECT_EQ(f.RecordCount("ATT"), 3u);
  EXPECT_EQ(f.RecordCount("MODE"), 2u);
  EXPECT_EQ(AllRecords(f), 10u);
}

TEST(DataflashFile, PaddingAtTheEndIsNoDamageButOtherBytesAre) {
  const std::string log = testing::FlightLog().bytes();
  const DataflashFile zeros = Parse(log + std::string(32, '\0'), "zeros.bin");
  EXPECT_TRUE(zeros.complete()) << zeros.problem;
  EXPECT_EQ(zeros.bytes_skipped, 0u);
  ASSERT_EQ(zeros.notes.size(), 1u);
  EXPECT_TRUE(Holds(zeros.notes[0], "32 bytes of 0x00 padding")) << zeros.notes[0];
  const DataflashFile erased = Parse(log + std::string(16, '\xff'), "erased.bin");
  EXPECT_TRUE(erased.complete()) << erased.problem;
  EXPECT_EQ(AllRecords(erased), 10u);

  const DataflashFile tail = Parse(log + "xyz", "tail.bin");
  EXPECT_FALSE(tail.complete());
  EXPECT_EQ(tail.problem_offset, 508u);
  EXPECT_EQ(tail.bytes_skipped, 3u);
  EXPECT_TRUE(Holds(tail.problem, "the end of the file")) << tail.problem;
}

TEST(DataflashFile, AnFmtTooShortForAHeaderIsRefused) {
  DataflashWriter w = testing::FlightLog();
  const std::size_t fmt_at = w.Fmt(140, "SHRT", "Q", "TimeUS", 2);
  w.Raw(std::string{'\xA3', '\x95', '\x8c'} + std::string(8, '\x01'));
  const DataflashFile f = Parse(w.bytes(), "short.bin");
  EXPECT_EQ(f.problem_offset, fmt_at);
  EXPECT_TRUE(Holds(f.problem, "a length of 2 bytes")) << f.problem;
  EXPECT_EQ(f.damage_count, 2u);  // and the record it could not frame
  EXPECT_EQ(f.unknown_type_counts.at(140), 1u);
  EXPECT_EQ(f.bytes_skipped, 11u);
  EXPECT_EQ(f.FindFormat("SHRT"), nullptr);
}

TEST(DataflashFile, RecordsOfAnUndecodableFormatAreFramedAndCounted) {
  DataflashWriter w = testing::FlightLog();
  w.Fmt(141, "BAD", "Qx", "TimeUS,X", 14);
  w.Raw(std::string{'\xA3', '\x95', '\x8d'} + std::string(11, '\x02'));
  w.Fmt(142, "LONG", "QQ", "TimeUS,A", 12);
  w.Raw(std::string{'\xA3', '\x95', '\x8e'} + std::string(9, '\x03'));
  w.Record(129, {1300000, 180, -220, 3});
  const DataflashFile f = Parse(w.bytes(), "undecodable.bin");
  EXPECT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.RecordCount("BAD"), 1u);
  EXPECT_EQ(f.RecordCount("LONG"), 1u);
  EXPECT_EQ(f.RecordCount("ATT"), 4u);
  const MessageFormat* bad = f.FindFormat("BAD");
  ASSERT_NE(bad, nullptr);
  EXPECT_FALSE(bad->decodable());
  EXPECT_TRUE(bad->fields.empty());
  EXPECT_TRUE(Holds(bad->undecodable, "'x'")) << bad->undecodable;
  EXPECT_TRUE(Holds(f.FindFormat("LONG")->undecodable, "needs 16 payload bytes"));
  ASSERT_EQ(f.notes.size(), 2u);
  EXPECT_TRUE(Holds(f.notes[0], "'BAD' (type 141, 14 bytes) cannot be decoded")) << f.notes[0];
}

TEST(DataflashFile, AnFmtIsRepeatedFreelyButNotRedefinedAfterRecords) {
  DataflashWriter w = testing::FlightLog();
  w.Fmt(129, "ATT", "QccC", "TimeUS,Roll,Pitch,Yaw");  // the same again: nothing to say
  EXPECT_TRUE(Parse(w.bytes(), "again.bin").complete());
  EXPECT_TRUE(Parse(w.bytes(), "again.bin").notes.empty());
  const std::size_t redefined_at = w.Fmt(129, "ATT", "Qcc", "TimeUS,Roll,Pitch");
  const DataflashFile f = Parse(w.bytes(), "redefined.bin");
  EXPECT_EQ(f.problem_offset, redefined_at);
  EXPECT_TRUE(Holds(f.problem, "redefines 'ATT' (type 129, 17 bytes), after 3 of its records"))
      << f.problem;
  EXPECT_EQ(f.FindFormat("ATT")->length, 17u);

  // Before any record of it, a type may be given another layout and name.
  DataflashWriter early;
  early.Fmt(150, "AAA", "Qf", "TimeUS,X");
  early.Fmt(150, "BBB", "Qh", "TimeUS,Y");
  early.Record(150, {1000, 7});
  const DataflashFile e = Parse(early.bytes(), "early.bin");
  EXPECT_TRUE(e.complete()) << e.problem;
  EXPECT_EQ(e.FindFormat("AAA"), nullptr);
  ASSERT_NE(e.FindFormat("BBB"), nullptr);
  EXPECT_EQ(e.FindFormat("BBB")->format, "Qh");
  EXPECT_EQ(e.RecordCount("BBB"), 1u);
  ASSERT_EQ(e.notes.size(), 1u);
  EXPECT_TRUE(Holds(e.notes[0], "redefines 'AAA'")) << e.notes[0];
}

TEST(DataflashFile, ASecondTypeOfTheSameNameIsCountedNotKept) {
  DataflashWriter w = testing::FlightLog();
  const std::size_t clash_at = w.Fmt(142, "ATT", "Qf", "TimeUS,X");
  w.Record(142, {1300000, 1.5});
  const DataflashFile f = Parse(w.bytes(), "clash.bin");
  EXPECT_EQ(f.problem_offset, clash_at);
  EXPECT_TRUE(Holds(f.problem, "the name of type 129")) << f.problem;
  EXPECT_EQ(f.record_counts.at(142), 1u);
  EXPECT_EQ(f.RecordCount("ATT"), 3u);
  EXPECT_EQ(f.FindFormat("ATT")->type, 129);
}

}  // namespace
}  // namespace odonata::dataflash

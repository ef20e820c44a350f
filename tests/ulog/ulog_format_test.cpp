// ULog formats: parsing 'F' texts, and flattening a subscribed format into the fields a data
// message holds, at their offsets (nested formats, arrays, padding inside and at the end).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <map>
#include <string>

#include "ulog/ulog_format.hpp"
#include "ulog/ulog_value.hpp"
#include "ulog_writer.hpp"

namespace odonata::ulog {
namespace {

std::map<std::string, Format> Formats(std::initializer_list<std::string_view> texts) {
  std::map<std::string, Format> m;
  for (const auto t : texts) {
    Format f = ParseFormat(t);
    m.emplace(f.name, std::move(f));
  }
  return m;
}

Layout Resolve(const std::string& name, const std::map<std::string, Format>& formats) {
  std::size_t budget = 100000;
  return ResolveLayout(name, formats, budget);
}

TEST(UlogFormat, ParsesNamesTypesArraysAndPadding) {
  const Format f =
      ParseFormat("m:uint64_t timestamp;float[4] q;esc_report[8] esc;uint8_t[3] _padding0;");
  EXPECT_EQ(f.name, "m");
  ASSERT_EQ(f.fields.size(), 4u);
  EXPECT_EQ(f.fields[0].type.name, "uint64_t");
  EXPECT_FALSE(f.fields[0].type.array_length.has_value());
  EXPECT_EQ(f.fields[1].name, "q");
  EXPECT_EQ(f.fields[1].type.array_length, 4u);
  EXPECT_EQ(f.fields[2].type.name, "esc_report");
  EXPECT_EQ(f.fields[2].type.count(), 8u);
  EXPECT_TRUE(f.fields[3].IsPadding());
  EXPECT_FALSE(f.fields[1].IsPadding());
  // The last ';' is optional; names may hold '-' and '/', as the spec allows.
  EXPECT_EQ(ParseFormat("a/b-c:uint8_t x").fields.size(), 1u);
}

TEST(UlogFormat, RefusesMalformedTexts) {
  for (const char* bad :
       {"no colon", ":uint8_t x;", "m:", "m:;;", "m:uint8_t;", "m:float[] x;", "m:float[x] x;",
        "m:float[4 x;", "m:float[123456] x;", "m:uint8_t a.b;", "m:uint8_t x;uint8_t x;",
        "float:uint8_t x;", "m.n:uint8_t x;", "m:uint8_t q[2];"}) {
    EXPECT_THROW(ParseFormat(bad), UlogError) << bad;
  }
}

TEST(UlogFormat, FlattensNestedFormatsArraysAndPadding) {
  const auto formats =
      Formats({testing::kSensorFormat, testing::kVec3Format, testing::kWheelFormat});
  const Layout l = Resolve("sensor", formats);
  EXPECT_EQ(l.size, testing::kSensorSize);
  EXPECT_EQ(l.logged_size, testing::kSensorLoggedSize);
  EXPECT_EQ(l.timestamp_offset, 0u);
  struct Expected {
    const char* path;
    BasicType type;
    std::size_t offset, count;
    bool is_array;
  };
  const Expected expected[] = {
      {"timestamp", BasicType::kUint64, 0, 1, false},
      {"i8", BasicType::kInt8, 8, 1, false},
      {"u8", BasicType::kUint8, 9, 1, false},
      {"i16", BasicType::kInt16, 10, 1, false},
      {"u16", BasicType::kUint16, 12, 1, false},
      {"i32", BasicType::kInt32, 14, 1, false},
      {"u32", BasicType::kUint32, 18, 1, false},
      {"i64", BasicType::kInt64, 22, 1, false},
      {"u64", BasicType::kUint64, 30, 1, false},
      {"f", BasicType::kFloat, 38, 1, false},
      {"d", BasicType::kDouble, 42, 1, false},
      {"b", BasicType::kBool, 50, 1, false},
      {"c", BasicType::kChar, 51, 1, false},
      {"label", BasicType::kChar, 52, 6, true},
      {"q", BasicType::kFloat, 58, 4, true},
      {"accel.x", BasicType::kFloat, 74, 1, false},
      {"accel.y", BasicType::kFloat, 78, 1, false},
      {"accel.z", BasicType::kFloat, 82, 1, false},
      {"mags[0].x", BasicType::kFloat, 86, 1, false},
      {"mags[0].y", BasicType::kFloat, 90, 1, false},
      {"mags[0].z", BasicType::kFloat, 94, 1, false},
      {"mags[1].x", BasicType::kFloat, 98, 1, false},
      {"mags[1].y", BasicType::kFloat, 102, 1, false},
      {"mags[1].z", BasicType::kFloat, 106, 1, false},
      {"wheels[0].rpm", BasicType::kUint16, 110, 1, false},  // its padding is no field
      {"wheels[1].rpm", BasicType::kUint16, 114, 1, false},
  };
  ASSERT_EQ(l.fields.size(), std::size(expected));
  for (std::size_t i = 0; i < l.fields.size(); ++i) {
    SCOPED_TRACE(expected[i].path);
    EXPECT_EQ(l.fields[i].path, expected[i].path);
    EXPECT_EQ(l.fields[i].type, expected[i].type);
    EXPECT_EQ(l.fields[i].offset, expected[i].offset);
    EXPECT_EQ(l.fields[i].count, expected[i].count);
    EXPECT_EQ(l.fields[i].is_array, expected[i].is_array);
  }
  ASSERT_NE(l.Find("mags[1].y"), nullptr);
  EXPECT_EQ(l.Find("mags[1].y")->offset, 102u);
  EXPECT_EQ(l.Find("_padding0"), nullptr);
}

TEST(UlogFormat, OnlyTheTopLevelTrailingPaddingIsLeftOut) {
  // The timestamp need not come first; padding in the middle stays; several pads at the end go.
  const auto formats = Formats({"inner:uint8_t a;uint8_t[3] _padding0;",
                                "outer:uint32_t n;uint8_t[4] _padding0;uint64_t timestamp;"
                                "inner[2] in;uint8_t[2] _padding1;uint8_t[1] _padding2;"});
  const Layout l = Resolve("outer", formats);
  EXPECT_EQ(l.size, 4u + 4 + 8 + 8 + 3);
  EXPECT_EQ(l.logged_size, 24u);  // inner[1]'s own padding is inside it, so it stays
  EXPECT_EQ(l.timestamp_offset, 8u);
  ASSERT_EQ(l.fields.size(), 4u);
  EXPECT_EQ(l.fields[3].path, "in[1].a");
  EXPECT_EQ(l.fields[3].offset, 20u);
}

TEST(UlogFormat, RefusesLayoutsThatCannotBeRead) {
  // Unknown type, cycle, no timestamp, a timestamp of another type, too large for a message.
  EXPECT_THROW(Resolve("a", Formats({"a:uint64_t timestamp;b x;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:uint64_t timestamp;b x;", "b:a y;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:uint64_t timestamp;a x;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:float x;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:uint32_t timestamp;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:uint64_t[1] timestamp;"})), UlogError);
  EXPECT_THROW(Resolve("a", Formats({"a:uint64_t timestamp;double[9000] x;"})), UlogError);
  EXPECT_THROW(Resolve("missing", Formats({"a:uint64_t timestamp;"})), UlogError);
  try {
    Resolve("a", Formats({"a:uint64_t timestamp;b x;", "b:c y;", "c:b z;"}));
    ADD_FAILURE() << "a cycle was accepted";
  } catch (const UlogError& e) {
    EXPECT_NE(std::string(e.what()).find("b -> c -> b"), std::string::npos) << e.what();
  }
}

TEST(UlogFormat, AFieldBudgetBoundsWhatAHostileFileCosts) {
  // One byte nested 60000 times makes 60000 fields; the budget stops it.
  const auto formats = Formats({"one:uint8_t v;", "big:uint64_t timestamp;one[60000] o;"});
  std::size_t budget = 1000;
  EXPECT_THROW(ResolveLayout("big", formats, budget), UlogError);
  std::size_t enough = 60001;
  EXPECT_EQ(ResolveLayout("big", formats, enough).fields.size(), 60001u);
  EXPECT_EQ(enough, 0u);
  // Zero-length arrays make no field, however deep they nest.
  const auto empty = Formats({"e:char[0] s;", "m:e[60000] x;", "t:uint64_t timestamp;m[60000] y;"});
  std::size_t small = 10;
  EXPECT_EQ(ResolveLayout("t", empty, small).fields.size(), 1u);
}

TEST(UlogFormat, ReadsEveryBasicTypeLittleEndian) {
  const auto bytes = [](std::initializer_list<int> b) {
    std::string s;
    for (const int v : b) s.push_back(static_cast<char>(v));
    return s;
  };
  const auto read = [](const std::string& s, BasicType t) {
    return ReadAsDouble(reinterpret_cast<const std::uint8_t*>(s.data()), t);
  };
  EXPECT_EQ(read(bytes({0x80}), BasicType::kInt8), -128.0);
  EXPECT_EQ(read(bytes({0xff}), BasicType::kUint8), 255.0);
  EXPECT_EQ(read(bytes({0x00, 0x80}), BasicType::kInt16), -32768.0);
  EXPECT_EQ(read(bytes({0xff, 0xff}), BasicType::kUint16), 65535.0);
  EXPECT_EQ(read(bytes({0x00, 0x00, 0x00, 0x80}), BasicType::kInt32), -2147483648.0);
  EXPECT_EQ(read(bytes({0xff, 0xff, 0xff, 0xff}), BasicType::kUint32), 4294967295.0);
  EXPECT_EQ(read(bytes({1, 0, 0, 0, 0, 0, 0, 0x80}), BasicType::kInt64),
            static_cast<double>(std::numeric_limits<std::int64_t>::min() + 1));
  EXPECT_EQ(read(bytes({0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0x1f, 0}), BasicType::kUint64),
            9007199254740991.0);  // 2^53 - 1, exact
  EXPECT_EQ(read(bytes({0, 0, 0xc0, 0x3f}), BasicType::kFloat), 1.5);
  EXPECT_EQ(read(bytes({0, 0, 0, 0, 0, 0, 0xf0, 0xbf}), BasicType::kDouble), -1.0);
  EXPECT_EQ(read(bytes({2}), BasicType::kBool), 1.0);  // any non-zero byte is true
  EXPECT_EQ(read(bytes({'A'}), BasicType::kChar), 65.0);
  EXPECT_TRUE(std::isnan(read(bytes({0, 0, 0xc0, 0x7f}), BasicType::kFloat)));
  // Unaligned: a field at an odd offset reads the same.
  const std::string odd = bytes({0x00, 0x00, 0x00, 0xc0, 0x3f});
  EXPECT_EQ(ReadAsDouble(reinterpret_cast<const std::uint8_t*>(odd.data()) + 1, BasicType::kFloat),
            1.5);
}

TEST(UlogValue, SplitsKeysAndChecksValueSizes) {
  const NamedValue v = ParseNamedValue("int32_t time_ref_utc", std::string("\xf0\xf1\xff\xff", 4));
  EXPECT_EQ(v.name, "time_ref_utc");
  EXPECT_EQ(v.value.type, "int32_t");
  EXPECT_EQ(v.value.Integer(), -3600);
  EXPECT_EQ(v.value.Number(), -3600.0);
  EXPECT_FALSE(v.value.IsText());
  const NamedValue text = ParseNamedValue("char[3] sys_name", std::string("PX4\0", 4));
  EXPECT_TRUE(text.value.IsText());
  EXPECT_EQ(text.value.Text(), "PX4");  // trailing NUL dropped, the bytes kept
  EXPECT_EQ(text.value.bytes.size(), 4u);
  EXPECT_FALSE(text.value.Number().has_value());
  const NamedValue arr = ParseNamedValue("float[2] xy", std::string(8, '\0'));
  EXPECT_FALSE(arr.value.Number().has_value());
  EXPECT_EQ(ParseNamedValue("my_type v", "anything").value.bytes, "anything");
  EXPECT_THROW(ParseNamedValue("int32_t x", "abc"), UlogError);
  EXPECT_THROW(ParseNamedValue("float[2] xy", "abcd"), UlogError);
  EXPECT_THROW(ParseNamedValue("nospace", ""), UlogError);
  EXPECT_THROW(ParseNamedValue("int32_t ", "abcd"), UlogError);
  TypedValue big{"uint64_t", std::string(8, '\xff')};
  EXPECT_FALSE(big.Integer().has_value());  // above INT64_MAX
  EXPECT_EQ(big.Number(), 18446744073709551615.0);
}

TEST(UlogValue, ContinuationsJoinAndKeepTheTypeTrue) {
  TypedValue v{"char[5]", "abcde"};
  AppendContinuation(v, "fgh");
  EXPECT_EQ(v.type, "char[8]");
  EXPECT_EQ(v.Text(), "abcdefgh");
  TypedValue w{"uint16_t[1]", std::string(2, '\0')};
  AppendContinuation(w, std::string(4, '\1'));
  EXPECT_EQ(w.type, "uint16_t[3]");
}

}  // namespace
}  // namespace odonata::ulog

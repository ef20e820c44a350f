// The real Crazyflie micro-SD logs of shared/crazyflie-usd (log06: the fixed-frequency block and
// events; log00: events only), when the build found them (ODONATA_CRAZYFLIE_USD_DIR; skipped
// otherwise): read whole, record counts against an independent walk of the bytes, values against
// an independent decoder, cuts and flipped bytes read cleanly, and the signals by their names.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "crazyflie_usd/usd_log_signals.hpp"
#include "usd_log_test_support.hpp"

namespace odonata::crazyflie_usd {
namespace {

using testing::Contains;
using testing::ExpectRecordsOf;

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The least a reader must do, written apart from the one under test with plain byte arithmetic:
// each type's id and bytes of values from the header, then the records' ids.
struct RecordWalk {
  std::map<std::uint16_t, std::size_t> records;  // per type id, every declared id
  std::vector<std::size_t> ends;                 // where each record ends
  std::size_t header_end = 0, end = 0;
};

RecordWalk WalkRecords(const std::string& b) {
  RecordWalk w;
  const auto u8 = [&b](std::size_t i) {
    return static_cast<std::size_t>(static_cast<unsigned char>(b[i]));
  };
  const auto u16 = [&u8](std::size_t i) { return u8(i) | u8(i + 1) << 8; };
  std::map<std::size_t, std::size_t> value_bytes;  // id -> bytes of a record's values
  std::size_t pos = 5;
  for (std::size_t k = 0, types = u16(3); k < types; ++k) {
    const std::size_t id = u16(pos);
    pos = b.find('\0', pos + 2) + 1;  // past the name
    const std::size_t variables = u16(pos);
    pos += 2;
    std::size_t bytes = 0;
    for (std::size_t j = 0; j < variables; ++j) {
      const std::size_t nul = b.find('\0', pos);
      const char code = b[nul - 2];  // "name(T)"
      bytes += code == 'B' || code == 'b' ? 1 : code == 'H' || code == 'h' || code == 'e' ? 2 : 4;
      pos = nul + 1;
    }
    value_bytes[id] = bytes;
    w.records[static_cast<std::uint16_t>(id)] = 0;
  }
  w.header_end = pos;
  const std::size_t stamp = u16(1) == 1 ? 4 : 8;
  while (pos + 2 + stamp <= b.size() - 4) {
    const std::size_t id = u16(pos);
    ++w.records[static_cast<std::uint16_t>(id)];
    pos += 2 + stamp + value_bytes.at(id);
    w.ends.push_back(pos);
  }
  w.end = pos;
  return w;
}

void ExpectCountsMatchTheWalk(const UsdLogFile& f, const RecordWalk& w) {
  EXPECT_EQ(f.header_size, w.header_end);
  EXPECT_EQ(f.file_size, w.end + 4);
  ASSERT_EQ(f.event_types.size(), w.records.size());
  std::size_t all = 0;
  for (const EventType& t : f.event_types) {
    EXPECT_EQ(t.size(), w.records.at(t.id)) << t.name;
    all += t.size();
  }
  EXPECT_EQ(f.records, all);
  EXPECT_EQ(w.ends.size(), all);
}

// Cut at every byte of the header and the first records, then at 40 places over the rest; 40
// bytes flipped: a clean partial read, or (in the first 5 bytes) a clear error.
void ExpectCutsAndFlipsReadCleanly(const std::string& bytes, const RecordWalk& w) {
  const UsdLogFile whole = Parse(bytes, "whole");
  std::vector<std::size_t> cuts;
  for (std::size_t cut = 0; cut < w.header_end + 200; ++cut) cuts.push_back(cut);
  for (std::size_t cut = w.header_end + 200; cut < bytes.size(); cut += bytes.size() / 40)
    cuts.push_back(cut);
  for (const std::size_t cut : cuts) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    if (cut < 5) {
      EXPECT_THROW((void)Parse(bytes.substr(0, cut), "cut"), UsdLogError);
      continue;
    }
    const UsdLogFile f = Parse(bytes.substr(0, cut), "cut");
    EXPECT_FALSE(f.intact());
    const std::size_t read =
        cut < w.header_end + 4
            ? 0
            : static_cast<std::size_t>(std::upper_bound(w.ends.begin(), w.ends.end(), cut - 4) -
                                       w.ends.begin());
    EXPECT_EQ(f.records, read);
    if (!f.complete()) {
      EXPECT_LE(f.problem_offset, cut);
    }
    ExpectRecordsOf(f, whole);
  }
  for (std::size_t i = 0; i < bytes.size(); i += bytes.size() / 40 + 1) {
    SCOPED_TRACE("byte " + std::to_string(i) + " flipped");
    std::string b = bytes;
    b[i] = static_cast<char>(b[i] ^ '\xff');
    if (i < 5 && !LooksLikeUsdLog(b)) continue;
    const UsdLogFile f = Parse(b, "flipped");
    EXPECT_FALSE(f.intact());
  }
}

// Built only when shared/crazyflie-usd was found at configure time (CMakeLists.txt).
class UsdLogRealFiles : public ::testing::Test {
 protected:
  static std::string PathOf(const char* file) {
    return std::string(ODONATA_CRAZYFLIE_USD_DIR) + "/" + file;
  }
};

// Values below: from an independent Python decoder of the same bytes (struct.unpack('<HQ') for
// each record's id and µs time, then '<' + the declared codes, e.g. '<fff'; zlib.crc32 over all
// but the last 4 bytes), printed with repr(): the float's exact value as a double.

TEST_F(UsdLogRealFiles, Log06FixedFrequencyAndEvents) {
  const std::string path = PathOf("log06");
  const UsdLogFile f = Read(path);
  ASSERT_TRUE(f.intact()) << f.problem;
  EXPECT_TRUE(f.notes.empty());
  EXPECT_EQ(f.version, 2);
  EXPECT_EQ(f.crc_stored, 0xc7cedcecu);
  const std::string bytes = FileBytes(path);
  const RecordWalk w = WalkRecords(bytes);
  ExpectCountsMatchTheWalk(f, w);
  EXPECT_EQ(f.RecordCount(kFixedFrequencyId), 1983u);
  EXPECT_EQ(f.RecordCount(8), 182u);
  EXPECT_EQ(f.RecordCount(3), 7930u);
  EXPECT_EQ(f.RecordCount(2), 7930u);
  EXPECT_EQ(f.RecordCount(1), 397u);

  const EventType* gyro = f.FindType(3);
  ASSERT_NE(gyro, nullptr);
  EXPECT_EQ(gyro->name, "estGyroscope");
  EXPECT_EQ(gyro->time_us.front(), 25625225u);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 0), 0.11252440512180328);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 1), -0.10904691368341446);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 2), -0.010666655376553535);
  EXPECT_EQ(gyro->time_us.back(), 33454266u);
  EXPECT_DOUBLE_EQ(gyro->Value(gyro->size() - 1, 0), -0.06667352467775345);

  const EventType* fixed = f.FindType(kFixedFrequencyId);
  ASSERT_NE(fixed, nullptr);
  EXPECT_EQ(fixed->name, "fixedFrequency");
  ASSERT_EQ(fixed->variables.size(), 3u);
  EXPECT_EQ(fixed->variables[2].name, "stateEstimate.z");
  EXPECT_EQ(fixed->time_us.front(), 25625311u);
  EXPECT_DOUBLE_EQ(fixed->Value(0, 0), -1.6310949325561523);
  EXPECT_DOUBLE_EQ(fixed->Value(0, 1), -0.17430266737937927);
  EXPECT_DOUBLE_EQ(fixed->Value(0, 2), 0.01054348237812519);

  const EventType* tof = f.FindType(8);
  ASSERT_NE(tof, nullptr);
  EXPECT_EQ(tof->variables[0].name, "kalman_mm.tofDistance");
  EXPECT_EQ(tof->time_us.front(), 25658634u);
  EXPECT_DOUBLE_EQ(tof->Value(0, 0), 0.02200000174343586);
  EXPECT_DOUBLE_EQ(tof->Value(0, 1), 0.002501794835552573);

  ExpectCutsAndFlipsReadCleanly(bytes, w);
}

TEST_F(UsdLogRealFiles, Log00EventsOnly) {
  const std::string path = PathOf("log00");
  const UsdLogFile f = Read(path);
  ASSERT_TRUE(f.intact()) << f.problem;
  EXPECT_EQ(f.crc_stored, 0x70033d6au);
  const std::string bytes = FileBytes(path);
  const RecordWalk w = WalkRecords(bytes);
  ExpectCountsMatchTheWalk(f, w);
  EXPECT_EQ(f.event_types.size(), 12u);
  EXPECT_EQ(f.FindType(kFixedFrequencyId), nullptr);
  const std::map<std::uint16_t, std::size_t> counts = {{12, 0},  {11, 0},    {10, 0},    {9, 0},
                                                       {8, 386}, {7, 0},     {6, 1583},  {5, 0},
                                                       {4, 0},   {3, 18935}, {2, 18934}, {1, 946}};
  for (const auto& [id, n] : counts) EXPECT_EQ(f.RecordCount(id), n) << id;

  // Payload fields are declared without a group.
  const EventType* tdoa = f.FindType(12);
  ASSERT_NE(tdoa, nullptr);
  EXPECT_EQ(tdoa->name, "estTDOA");
  ASSERT_EQ(tdoa->variables.size(), 3u);
  EXPECT_EQ(tdoa->variables[2].name, "distanceDiff");

  const EventType* gyro = f.FindType(3);
  ASSERT_NE(gyro, nullptr);
  EXPECT_EQ(gyro->time_us.front(), 3341356u);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 0), 0.06203009560704231);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 1), -0.1847650110721588);
  EXPECT_DOUBLE_EQ(gyro->Value(0, 2), -0.2841567397117615);

  const EventType* flow = f.FindType(6);
  ASSERT_NE(flow, nullptr);
  EXPECT_EQ(flow->variables[1].name, "motion.deltaY");
  EXPECT_EQ(flow->variables[1].code, 'h');
  EXPECT_EQ(flow->time_us.front(), 5576304u);
  EXPECT_EQ(flow->Value(0, 0), -4.0);
  EXPECT_EQ(flow->Value(0, 1), -2.0);

  const EventType* tof = f.FindType(8);
  ASSERT_NE(tof, nullptr);
  EXPECT_EQ(tof->variables[0].name, "range.zrange");
  EXPECT_EQ(tof->variables[0].code, 'H');
  EXPECT_EQ(tof->time_us[2], 5635852u);
  EXPECT_EQ(tof->Value(2, 0), 6.0);

  const EventType* baro = f.FindType(1);
  ASSERT_NE(baro, nullptr);
  EXPECT_EQ(baro->time_us.front(), 3341611u);
  EXPECT_DOUBLE_EQ(baro->Value(0, 0), -160.86422729492188);

  ExpectCutsAndFlipsReadCleanly(bytes, w);
}

TEST_F(UsdLogRealFiles, Log06SignalsByTheirCrazyflieNames) {
  const UsdLogFile f = Read(PathOf("log06"));
  const std::vector<SignalInfo> signals = ListSignals(f);
  std::vector<std::string> names;
  for (const SignalInfo& s : signals) names.push_back(s.name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"stateEstimate.x", "stateEstimate.y", "stateEstimate.z",
                                      "kalman_mm.tofDistance", "kalman_mm.tofStdDev", "gyro.x",
                                      "gyro.y", "gyro.z", "acc.x", "acc.y", "acc.z", "baro.asl"}));
  ASSERT_EQ(signals.size(), 12u);
  // Median rates (1 / the median interval, as the same Python decoder finds them): 252.84 Hz for
  // the fixed-frequency block, 1013.17 Hz for the gyroscope.
  EXPECT_EQ(signals[2].event, "fixedFrequency");
  EXPECT_EQ(signals[2].samples, 1983u);
  EXPECT_NEAR(signals[2].median_rate_hz, 252.8445, 1e-3);
  EXPECT_EQ(signals[5].event, "estGyroscope");
  EXPECT_EQ(signals[5].type, "float");
  EXPECT_EQ(signals[5].out_of_order, 0u);
  EXPECT_NEAR(signals[5].median_rate_hz, 1013.1712, 1e-3);

  const timeseries::TimedSignal z = Extract(f, "stateEstimate.z");
  ASSERT_EQ(z.t_s.size(), 1983u);
  EXPECT_DOUBLE_EQ(z.t_s.front(), 25.625311);
  EXPECT_DOUBLE_EQ(z.values.front(), 0.01054348237812519);
  EXPECT_EQ(z.interpolation, timeseries::Interpolation::kLinear);
  const timeseries::TimedSignal x = Extract(f, "gyro.x");
  EXPECT_EQ(Extract(f, "estGyroscope:gyro.x").values, x.values);
  EXPECT_DOUBLE_EQ(x.t_s.front(), 25.625225);
  EXPECT_DOUBLE_EQ(x.values.front(), 0.11252440512180328);
}

TEST_F(UsdLogRealFiles, Log00SignalsSayWhatWasNeverLogged) {
  const UsdLogFile f = Read(PathOf("log00"));
  const std::vector<SignalInfo> signals = ListSignals(f);
  ASSERT_EQ(signals.size(), 10u);  // estTOF 1, estFlow 2, gyroscope 3, accelerometer 3, baro 1
  EXPECT_EQ(signals[0].name, "range.zrange");
  EXPECT_EQ(signals[0].type, "uint16_t");
  EXPECT_EQ(signals[1].name, "motion.deltaX");
  EXPECT_EQ(signals[1].interpolation, timeseries::Interpolation::kLinear);
  EXPECT_EQ(Extract(f, "motion.deltaY").values.front(), -2.0);
  try {
    (void)Extract(f, "estTDOA.distanceDiff");
    ADD_FAILURE() << "a payload field of a type that logged no record is no signal";
  } catch (const std::invalid_argument& e) {
    EXPECT_TRUE(Contains(e.what(), "event type 'estTDOA' declares it but logged no record"))
        << e.what();
    EXPECT_TRUE(Contains(e.what(), "nearest: ")) << e.what();
  }
}

}  // namespace
}  // namespace odonata::crazyflie_usd

// Real ArduPilot logs (shared/ardupilot: ArduPlane, cut at 65 536 bytes; shared/mavlink: ArduSub
// 4.1 with units): record counts against an independent walk of the headers, the cut record with
// its offset, values against numbers decoded apart from this reader (dataflash_values_test.py,
// Python's struct module on the same bytes), and cuts and flipped bytes that never crash.
// tests/dataflash/CMakeLists.txt defines ODONATA_ARDUPILOT_DIR and ODONATA_MAVLINK_DIR when the
// folders are there; the tests of a missing one are skipped.
#include <gtest/gtest.h>

#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"

namespace odonata::dataflash {
namespace {

#if defined(ODONATA_ARDUPILOT_DIR) || defined(ODONATA_MAVLINK_DIR)

// From tests/dataflash/dataflash_values_test.py: an independent Python struct decoder of the same
// files (its --check compares these arrays with what it decodes). First five records each.
constexpr double kArduplaneAttPitchTimeS[] = {81.795644, 81.876327, 81.915123, 81.955788,
                                              82.010394};
constexpr double kArduplaneAttPitch[] = {2.58, 2.49, 2.5, 2.5500000000000003, 2.56};
constexpr double kArduplaneAttYawTimeS[] = {81.795644, 81.876327, 81.915123, 81.955788, 82.010394};
constexpr double kArduplaneAttYaw[] = {337.1, 337.08, 337.09000000000003, 337.09000000000003,
                                       337.08};
constexpr double kArduplaneImuGyrXTimeS[] = {81.794643, 81.814512, 81.854801, 81.875059, 81.914486};
constexpr double kArduplaneImuGyrX[] = {-0.1165708526968956, -0.13836318254470825,
                                        0.002554166130721569, 0.029215797781944275,
                                        0.025460582226514816};
constexpr double kArdusubAttPitchTimeS[] = {265.738465, 265.838459, 265.93844, 266.038473,
                                            266.138436};
constexpr double kArdusubAttPitch[] = {-0.63, -0.63, -0.63, -0.63, -0.63};
constexpr double kArdusubAttYawTimeS[] = {265.738465, 265.838459, 265.93844, 266.038473,
                                          266.138436};
constexpr double kArdusubAttYaw[] = {213.93, 213.93, 213.94, 213.94, 213.94};
constexpr double kArdusubImuGyrXTimeS[] = {265.678654, 265.718506, 265.758437, 265.798407,
                                           265.838492};
constexpr double kArdusubImuGyrX[] = {-0.007749793119728565, -0.008241569623351097,
                                      -0.008467644453048706, -0.006898356601595879,
                                      -0.008362583816051483};

std::string FileBytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The least a reader must do, written apart from the one under test: the headers, and the name
// and length of each type from its FMT record (type byte at 3, length at 4, name at 5..8).
struct HeaderWalk {
  std::map<std::string, std::size_t> records;  // per message name
  std::size_t total = 0;
  std::size_t end = 0;  // where the walk stopped: the end, or the start of a cut record
};

HeaderWalk WalkHeaders(const std::string& b) {
  HeaderWalk w;
  std::map<unsigned, std::pair<std::string, std::size_t>> types = {{128u, {"FMT", 89}}};
  const auto u8 = [&b](std::size_t i) {
    return static_cast<unsigned>(static_cast<unsigned char>(b[i]));
  };
  std::size_t pos = 0;
  while (pos + 3 <= b.size() && u8(pos) == 0xA3 && u8(pos + 1) == 0x95) {
    const auto it = types.find(u8(pos + 2));
    if (it == types.end() || pos + it->second.second > b.size()) break;
    const std::string name = it->second.first;
    const std::size_t length = it->second.second;
    if (u8(pos + 2) == 128) {
      const std::string defined = b.substr(pos + 5, 4);
      types[u8(pos + 3)] = {defined.substr(0, defined.find('\0')), u8(pos + 4)};
    }
    ++w.records[name];
    ++w.total;
    pos += length;
  }
  w.end = pos;
  return w;
}

void ExpectCountsOfTheWalk(const DataflashFile& f, const HeaderWalk& w) {
  for (const auto& [name, n] : w.records) EXPECT_EQ(f.RecordCount(name), n) << name;
  std::size_t total = 0;
  for (const auto& [type, n] : f.record_counts) total += n;
  EXPECT_EQ(total, w.total);
  for (const auto& [name, m] : f.messages)
    if (m.size() > 0) {
      EXPECT_EQ(w.records.count(name), 1u) << name;
    }
}

void ExpectFirstFive(const DataflashFile& f, const std::string& name, const double (&t_s)[5],
                     const double (&values)[5]) {
  const timeseries::TimedSignal s = Extract(f, name);
  ASSERT_GE(s.values.size(), 5u) << name;
  for (std::size_t i = 0; i < 5; ++i) {
    EXPECT_DOUBLE_EQ(s.t_s[i], t_s[i]) << name << " record " << i;
    EXPECT_DOUBLE_EQ(s.values[i], values[i]) << name << " record " << i;
  }
}

// Cuts (every byte of the first 512, then every 997th) and flipped bytes: a clean partial read
// that agrees with the independent walk of the same bytes, or a clear error, never a crash.
void ExpectCutsAndFlipsReadCleanly(const std::string& bytes) {
  for (std::size_t n = 3; n < bytes.size(); n += n < 512 ? 1 : 997) {
    SCOPED_TRACE(n);
    const std::string cut = bytes.substr(0, n);
    const DataflashFile f = Parse(cut, "cut.bin");
    const HeaderWalk w = WalkHeaders(cut);
    ExpectCountsOfTheWalk(f, w);
    EXPECT_EQ(f.complete(), w.end == n);
    if (!f.complete()) {
      EXPECT_EQ(f.problem_offset, w.end);
    }
  }
  for (std::size_t k = 0; k < 200; ++k) {
    const std::size_t at = 3 + (k * 7919) % (bytes.size() - 3);
    SCOPED_TRACE(at);
    std::string flipped = bytes;
    flipped[at] = static_cast<char>(flipped[at] ^ 0x5a);
    const DataflashFile f = Parse(flipped, "flipped.bin");
    EXPECT_LE(f.problem_offset, bytes.size());
    EXPECT_LE(f.bytes_skipped, bytes.size());
    const std::vector<SignalInfo> signals = ListSignals(f);
    for (std::size_t i = 0; i < signals.size(); i += 1 + signals.size() / 4)
      EXPECT_EQ(Extract(f, signals[i].name).values.size(), signals[i].samples);
  }
}

#endif  // either folder

#ifdef ODONATA_ARDUPILOT_DIR

const std::string kArduplanePath = std::string(ODONATA_ARDUPILOT_DIR) + "/arduplane_test.BIN";

TEST(DataflashRealFiles, ArduPlaneCutLogReadsEveryWholeRecord) {
  const DataflashFile f = Read(kArduplanePath);
  const HeaderWalk w = WalkHeaders(FileBytes(kArduplanePath));
  EXPECT_EQ(f.file_size, 65536u);
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(f.problem_offset, 65512u);
  EXPECT_EQ(w.end, 65512u);
  EXPECT_EQ(f.problem,
            "the last record, 'AHR2' (type 141, 45 bytes) at byte 65512, is cut: only 24 bytes "
            "are left");
  EXPECT_EQ(f.bytes_skipped, 24u);
  EXPECT_EQ(f.damage_count, 1u);
  EXPECT_TRUE(f.notes.empty());
  ExpectCountsOfTheWalk(f, w);
  EXPECT_EQ(w.total, 1731u);
  EXPECT_EQ(f.RecordCount("FMT"), 132u);
  EXPECT_EQ(f.RecordCount("PARM"), 809u);
  EXPECT_EQ(f.RecordCount("IMU"), 45u);
  EXPECT_EQ(f.RecordCount("IMU2"), 45u);
  EXPECT_EQ(f.RecordCount("ATT"), 24u);
  EXPECT_TRUE(f.units.empty());  // ArduPlane 3.8 logs no FMTU

  ExpectFirstFive(f, "ATT.Pitch", kArduplaneAttPitchTimeS, kArduplaneAttPitch);
  ExpectFirstFive(f, "ATT.Yaw", kArduplaneAttYawTimeS, kArduplaneAttYaw);
  ExpectFirstFive(f, "IMU.GyrX", kArduplaneImuGyrXTimeS, kArduplaneImuGyrX);

  std::map<std::string, SignalInfo> signals;
  for (const SignalInfo& s : ListSignals(f)) signals.emplace(s.name, s);
  EXPECT_NEAR(signals.at("IMU.GyrX").median_rate_hz, 49.94, 0.01);
  EXPECT_NEAR(signals.at("ATT.Pitch").median_rate_hz, 24.85, 0.01);
  EXPECT_EQ(signals.at("ATT.Pitch").samples, 24u);
  EXPECT_EQ(signals.at("IMU2.GyrX").samples, 45u);
  EXPECT_EQ(signals.at("RCOU.C3").samples, 23u);
  EXPECT_EQ(signals.at("MODE.Mode").interpolation, timeseries::Interpolation::kHold);
  EXPECT_EQ(signals.count("PARM.Name"), 0u);
  EXPECT_EQ(signals.count("PARM.Value"), 1u);
}

TEST(DataflashRealFiles, ArduPlaneCutsAndFlipsReadCleanly) {
  ExpectCutsAndFlipsReadCleanly(FileBytes(kArduplanePath));
}

#endif

#ifdef ODONATA_MAVLINK_DIR

const std::string kArdusubPath = std::string(ODONATA_MAVLINK_DIR) + "/ardusub_small.BIN";

TEST(DataflashRealFiles, ArduSubLogReadsCompletelyWithUnits) {
  const DataflashFile f = Read(kArdusubPath);
  const HeaderWalk w = WalkHeaders(FileBytes(kArdusubPath));
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.file_size, 294039u);
  EXPECT_EQ(w.end, f.file_size);
  EXPECT_EQ(f.bytes_skipped, 0u);
  EXPECT_TRUE(f.notes.empty());
  ExpectCountsOfTheWalk(f, w);
  EXPECT_EQ(w.total, 7510u);
  EXPECT_EQ(f.RecordCount("IMU"), 594u);
  EXPECT_EQ(f.RecordCount("ATT"), 237u);
  EXPECT_EQ(f.RecordCount("FMTU"), 152u);
  EXPECT_EQ(f.RecordCount("UNIT"), 34u);
  EXPECT_EQ(f.RecordCount("MULT"), 14u);
  EXPECT_EQ(f.unit_labels.at('d'), "deg");
  EXPECT_DOUBLE_EQ(f.multipliers.at('B'), 0.01);

  ExpectFirstFive(f, "ATT.Pitch", kArdusubAttPitchTimeS, kArdusubAttPitch);
  ExpectFirstFive(f, "ATT.Yaw", kArdusubAttYawTimeS, kArdusubAttYaw);
  ExpectFirstFive(f, "IMU.GyrX", kArdusubImuGyrXTimeS, kArdusubImuGyrX);
  // IMU's field I is its instance ('#'): all of this log's IMU records are instance 0.
  ExpectFirstFive(f, "IMU[0].GyrX", kArdusubImuGyrXTimeS, kArdusubImuGyrX);

  std::map<std::string, SignalInfo> signals;
  for (const SignalInfo& s : ListSignals(f)) signals.emplace(s.name, s);
  EXPECT_EQ(signals.at("ATT.Pitch").unit, "deg");
  EXPECT_EQ(signals.at("IMU.GyrX").unit, "rad/s");
  EXPECT_EQ(signals.at("IMU.GyrX").instance, 0);
  EXPECT_EQ(signals.at("IMU.GyrX").samples, 594u);
  EXPECT_NEAR(signals.at("IMU.GyrX").median_rate_hz, 25.0, 0.01);
  EXPECT_EQ(signals.count("IMU[1].GyrX"), 0u);
  EXPECT_EQ(signals.count("IMU.I"), 0u);
  EXPECT_EQ(signals.at("RATE.R").unit, "deg/s");
  EXPECT_NEAR(signals.at("RATE.R").median_rate_hz, 10.0, 0.01);
  EXPECT_EQ(signals.at("RCOU.C3").unit, "us");
  // Two barometers: instance 1 is named by its number.
  EXPECT_EQ(signals.at("BARO.Alt").samples, 237u);
  EXPECT_EQ(signals.at("BARO[1].Alt").samples, 237u);
  EXPECT_EQ(signals.at("BARO[1].Alt").instance, 1);
  EXPECT_EQ(signals.at("BARO[1].Alt").unit, "m");
  // MAG is logged in milligauss; FMTU's multiplier C (0.001) makes it gauss.
  EXPECT_EQ(signals.at("MAG.MagX").unit, "Gauss");
  EXPECT_DOUBLE_EQ(signals.at("MAG.MagX").multiplier, 0.001);
  EXPECT_EQ(signals.at("MODE.Mode").interpolation, timeseries::Interpolation::kHold);
}

TEST(DataflashRealFiles, ArduSubCutsAndFlipsReadCleanly) {
  ExpectCutsAndFlipsReadCleanly(FileBytes(kArdusubPath));
}

#endif

}  // namespace
}  // namespace odonata::dataflash

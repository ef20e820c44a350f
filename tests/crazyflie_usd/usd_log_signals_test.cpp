// The signals of a Crazyflie micro-SD log: named as Crazyflie users write them (a log variable by
// its name, a payload field under its event's), a name logged by several event types kept by the
// one with the most records, "eventName:name" always accepted; held flags; seconds on the
// Crazyflie's clock; records out of time order dropped and counted; a mistyped name answered with
// the nearest ones.
#include <gtest/gtest.h>

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "crazyflie_usd/usd_log_signals.hpp"
#include "usd_log_test_support.hpp"
#include "usd_log_writer.hpp"

namespace odonata::crazyflie_usd {
namespace {

using testing::Contains;

using testing::Packed;
using testing::UsdLogWriter;
using timeseries::Interpolation;

std::string ExtractError(const UsdLogFile& f, const std::string& name) {
  try {
    (void)Extract(f, name);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(no error)";
}

std::vector<std::string> Names(const std::vector<SignalInfo>& signals) {
  std::vector<std::string> names;
  for (const SignalInfo& s : signals) names.push_back(s.name);
  return names;
}

// gyro.x logged by two event types: 4 records of estGyroscope at 1 kHz, 2 of the fixed-frequency
// block; a payload (estTDOA) with a flag, and a declared type without records (estPose).
UsdLogFile TwoSourcesLog() {
  UsdLogWriter w(2, {{kFixedFrequencyId, "fixedFrequency", {"gyro.x(f)", "motor.m1(H)"}},
                     {3, "estGyroscope", {"gyro.x(f)", "gyro.y(f)", "gyro.x(f)"}},
                     {12, "estTDOA", {"idA(B)", "mode(b)", "distanceDiff(e)"}},
                     {10, "estPose", {"locSrv.qx(f)"}}});
  w.Record(kFixedFrequencyId, 1000000, Packed().F32(9).U16(100));
  for (int i = 0; i < 4; ++i)
    w.Record(3, 1000000 + 1000 * static_cast<std::uint64_t>(i),
             Packed().F32(static_cast<float>(i)).F32(-1).F32(static_cast<float>(i)));
  w.Record(kFixedFrequencyId, 1010000, Packed().F32(8).U16(200));
  w.Record(12, 1500000, Packed().U8(1).I8(-3).Half(0x3800));  // 0.5
  return Parse(w.Finish(), "two-sources.log");
}

TEST(UsdLogSignals, NamesAreTheCrazyflieOnes) {
  const UsdLogFile f = TwoSourcesLog();
  ASSERT_TRUE(f.intact()) << f.problem;
  const std::vector<SignalInfo> signals = ListSignals(f);
  // In the header's order; gyro.x declared twice by estGyroscope is one signal; estPose, without
  // records, has none.
  EXPECT_EQ(Names(signals),
            (std::vector<std::string>{"fixedFrequency:gyro.x", "motor.m1", "gyro.x", "gyro.y",
                                      "estTDOA.idA", "estTDOA.mode", "estTDOA.distanceDiff"}));
  ASSERT_EQ(signals.size(), 7u);
  EXPECT_EQ(signals[0].event, "fixedFrequency");
  EXPECT_EQ(signals[0].variable, "gyro.x");
  EXPECT_EQ(signals[2].event, "estGyroscope");
  EXPECT_EQ(signals[2].samples, 4u);
  EXPECT_EQ(signals[6].variable, "distanceDiff");
  EXPECT_EQ(signals[6].type, "half");
  EXPECT_EQ(signals[6].code, 'e');

  // The one with the most records keeps the plain name; every "eventName:name" is accepted.
  EXPECT_EQ(Extract(f, "gyro.x").values, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(Extract(f, "estGyroscope:gyro.x").values, (std::vector<double>{0, 1, 2, 3}));
  EXPECT_EQ(Extract(f, "fixedFrequency:gyro.x").values, (std::vector<double>{9, 8}));
  EXPECT_EQ(Extract(f, "fixedFrequency:motor.m1").values, (std::vector<double>{100, 200}));
  EXPECT_EQ(Extract(f, "estTDOA:distanceDiff").values, (std::vector<double>{0.5}));
  EXPECT_EQ(Extract(f, "estTDOA.mode").values, (std::vector<double>{-3}));
  EXPECT_EQ(Extract(f, "gyro.x").name, "gyro.x");
  EXPECT_EQ(Extract(f, "estGyroscope:gyro.x").name, "estGyroscope:gyro.x");
}

TEST(UsdLogSignals, OnATieTheFirstDeclaredKeepsThePlainName) {
  UsdLogWriter w(2, {{2, "estAcceleration", {"acc.z(f)"}},
                     {kFixedFrequencyId, "fixedFrequency", {"acc.z(f)"}}});
  w.Record(2, 1000, Packed().F32(1));
  w.Record(kFixedFrequencyId, 1000, Packed().F32(2));
  const UsdLogFile f = Parse(w.Finish(), "tie.log");
  EXPECT_EQ(Names(ListSignals(f)), (std::vector<std::string>{"acc.z", "fixedFrequency:acc.z"}));
  EXPECT_EQ(Extract(f, "acc.z").values, (std::vector<double>{1}));
}

TEST(UsdLogSignals, FlagsAreHeldAndTheRestInterpolated) {
  const std::vector<SignalInfo> signals = ListSignals(TwoSourcesLog());
  for (const SignalInfo& s : signals) {
    SCOPED_TRACE(s.name);
    const bool held = s.code == 'B' || s.code == 'b';
    EXPECT_EQ(s.interpolation, held ? Interpolation::kHold : Interpolation::kLinear);
  }
  EXPECT_EQ(signals[4].type, "uint8_t");
  EXPECT_EQ(signals[4].interpolation, Interpolation::kHold);
  EXPECT_EQ(signals[5].type, "int8_t");
  EXPECT_EQ(signals[1].type, "uint16_t");
  EXPECT_EQ(signals[1].interpolation, Interpolation::kLinear);
  EXPECT_EQ(Extract(TwoSourcesLog(), "estTDOA.idA").interpolation, Interpolation::kHold);
}

TEST(UsdLogSignals, TimesAreSecondsOnTheCrazyfliesClock) {
  const UsdLogFile f = TwoSourcesLog();
  EXPECT_EQ(Extract(f, "gyro.y").t_s, (std::vector<double>{1.0, 1.001, 1.002, 1.003}));
  EXPECT_EQ(Extract(f, "motor.m1").t_s, (std::vector<double>{1.0, 1.01}));
  const std::vector<SignalInfo> signals = ListSignals(f);
  EXPECT_NEAR(signals[2].median_rate_hz, 1000.0, 1e-6);
  EXPECT_NEAR(signals[1].median_rate_hz, 100.0, 1e-9);
  EXPECT_EQ(signals[6].median_rate_hz, 0.0);  // one record: no rate

  // Version 1 logs milliseconds.
  UsdLogWriter v1(1, {{1, "estBarometer", {"baro.asl(f)"}}});
  v1.Record(1, 1500, Packed().F32(-160)).Record(1, 1520, Packed().F32(-161));
  const UsdLogFile g = Parse(v1.Finish(), "v1.log");
  EXPECT_EQ(Extract(g, "baro.asl").t_s, (std::vector<double>{1.5, 1.52}));
  EXPECT_NEAR(ListSignals(g)[0].median_rate_hz, 50.0, 1e-9);
}

TEST(UsdLogSignals, ARecordEarlierThanTheOneBeforeIsDroppedAndCounted) {
  UsdLogWriter w(2, {{3, "estGyroscope", {"gyro.x(f)"}}});
  w.Record(3, 2000, Packed().F32(1));
  w.Record(3, 3000, Packed().F32(2));
  w.Record(3, 2500, Packed().F32(99));  // earlier than 3000
  w.Record(3, 3000, Packed().F32(3));   // equal times are kept
  w.Record(3, 4000, Packed().F32(4));
  const UsdLogFile f = Parse(w.Finish(), "backwards.log");
  const std::vector<SignalInfo> signals = ListSignals(f);
  ASSERT_EQ(signals.size(), 1u);
  EXPECT_EQ(signals[0].samples, 4u);
  EXPECT_EQ(signals[0].out_of_order, 1u);
  const timeseries::TimedSignal s = Extract(f, "gyro.x");
  EXPECT_EQ(s.values, (std::vector<double>{1, 2, 3, 4}));
  EXPECT_EQ(s.t_s, (std::vector<double>{0.002, 0.003, 0.003, 0.004}));
}

TEST(UsdLogSignals, AMistypedNameIsAnsweredWithTheFiveNearest) {
  const UsdLogFile f = TwoSourcesLog();
  const std::string e = ExtractError(f, "gyro.q");
  EXPECT_TRUE(Contains(e, "no signal 'gyro.q' in two-sources.log")) << e;
  const std::string nearest = e.substr(e.find("nearest: ") + 9);
  EXPECT_EQ(nearest, "gyro.x, gyro.y, motor.m1, estTDOA.idA, estTDOA.mode") << e;

  EXPECT_TRUE(Contains(ExtractError(f, "locSrv.qx"),
                       "event type 'estPose' declares it but logged no record"));
  EXPECT_TRUE(Contains(ExtractError(f, "estPose:locSrv.qx"), "logged no record"));
  EXPECT_TRUE(Contains(ExtractError(f, "estGyroscope.timestamp"), "own time axis"));

  const UsdLogFile empty = Parse(UsdLogWriter(2, {}).Finish(), "empty.log");
  EXPECT_TRUE(ListSignals(empty).empty());
  EXPECT_TRUE(Contains(ExtractError(empty, "gyro.x"), "it has no signals"))
      << ExtractError(empty, "gyro.x");
}

TEST(UsdLogSignals, APartialReadOffersWhatWasRead) {
  UsdLogWriter w(2, {{3, "estGyroscope", {"gyro.x(f)"}}});
  w.Record(3, 1000, Packed().F32(1)).Record(3, 2000, Packed().F32(2));
  w.Record(77, 3000);  // never declared: the reading stops here
  const UsdLogFile f = Parse(w.Finish(), "partial.log");
  EXPECT_FALSE(f.complete());
  EXPECT_EQ(Extract(f, "gyro.x").values, (std::vector<double>{1, 2}));
}

}  // namespace
}  // namespace odonata::crazyflie_usd

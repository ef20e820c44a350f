// Signals of a ULog file: their names (arrays, nested formats, instances), exact values, times
// that go backwards, publication rates, and resampling onto one grid with gaps left as NaN.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "io/csv_table.hpp"
#include "ulog/ulog_signals.hpp"
#include "ulog_writer.hpp"

namespace odonata::ulog {
namespace {

using testing::Payload;
using testing::UlogWriter;

constexpr std::uint64_t kStartUs = 1'000'000;

// Topic "a" (v = 2 t, 100 Hz) and "b" (v = -t + 1, 50 Hz, 3 ms later), t in seconds since the
// start; `a_times_us` overrides a's times.
UlogFile TwoRatesLog(const std::vector<std::uint64_t>& a_times_us = {}) {
  UlogWriter w(1, kStartUs);
  w.Format("a:uint64_t timestamp;double v;").Format("b:uint64_t timestamp;float v;int16_t n;");
  w.Subscribe(0, 0, "a").Subscribe(0, 1, "b");
  std::vector<std::uint64_t> a = a_times_us;
  if (a.empty())
    for (std::uint64_t i = 0; i <= 100; ++i) a.push_back(kStartUs + 10'000 * i);
  for (const std::uint64_t t : a)
    w.Data(0, Payload().Put(t).Put(2.0 * static_cast<double>(t - kStartUs) * 1e-6));
  for (std::uint64_t i = 0; i <= 50; ++i) {
    const std::uint64_t t = kStartUs + 3'000 + 20'000 * i;
    w.Data(1, Payload()
                  .Put(t)
                  .Put(static_cast<float>(1.0 - static_cast<double>(t - kStartUs) * 1e-6))
                  .Put(static_cast<std::int16_t>(i)));
  }
  return ParseStrict(w.bytes(), "two_rates.ulg");
}

std::vector<std::string> Names(const std::vector<SignalInfo>& signals) {
  std::vector<std::string> names;
  for (const auto& s : signals) names.push_back(s.name);
  return names;
}

TEST(UlogSignals, NamesFollowFieldsArraysNestingAndInstances) {
  const UlogFile f = ParseStrict(testing::EveryMessageKindLog().bytes(), "all.ulg");
  const std::vector<SignalInfo> signals = ListSignals(f);
  const std::vector<std::string> expected = {"sensor.i8",
                                             "sensor.u8",
                                             "sensor.i16",
                                             "sensor.u16",
                                             "sensor.i32",
                                             "sensor.u32",
                                             "sensor.i64",
                                             "sensor.u64",
                                             "sensor.f",
                                             "sensor.d",
                                             "sensor.b",
                                             "sensor.q[0]",
                                             "sensor.q[1]",
                                             "sensor.q[2]",
                                             "sensor.q[3]",
                                             "sensor.roll_rad",  // derived from q
                                             "sensor.pitch_rad",
                                             "sensor.yaw_rad",
                                             "sensor.accel.x",
                                             "sensor.accel.y",
                                             "sensor.accel.z",
                                             "sensor.mags[0].x",
                                             "sensor.mags[0].y",
                                             "sensor.mags[0].z",
                                             "sensor.mags[1].x",
                                             "sensor.mags[1].y",
                                             "sensor.mags[1].z",
                                             "sensor.wheels[0].rpm",
                                             "sensor.wheels[1].rpm",
                                             "motor.thrust[0]",
                                             "motor.thrust[1]",
                                             "motor/1.thrust[0]",
                                             "motor/1.thrust[1]"};
  EXPECT_EQ(Names(signals), expected);  // no timestamp, no char or char[] text, no padding
  EXPECT_EQ(signals[0].type, "int8_t");
  EXPECT_EQ(signals[9].type, "double");
  EXPECT_EQ(signals[10].type, "bool");
  EXPECT_EQ(signals[15].type, "derived");
  EXPECT_EQ(signals[27].type, "uint16_t");
  EXPECT_EQ(signals[0].samples, 3u);
  EXPECT_EQ(signals[0].median_rate_hz, 10.0);  // 100 ms apart
  EXPECT_EQ(signals[31].topic, "motor");
  EXPECT_EQ(signals[31].multi_id, 1);
  EXPECT_EQ(signals[31].samples, 2u);
  // Flags and 8-bit enumerations are held, everything else interpolated.
  EXPECT_EQ(signals[0].interpolation, timeseries::Interpolation::kHold);   // int8_t
  EXPECT_EQ(signals[1].interpolation, timeseries::Interpolation::kHold);   // uint8_t
  EXPECT_EQ(signals[10].interpolation, timeseries::Interpolation::kHold);  // bool
  EXPECT_EQ(signals[2].interpolation, timeseries::Interpolation::kLinear);
  EXPECT_EQ(signals[15].interpolation, timeseries::Interpolation::kLinear);
}

TEST(UlogSignals, ExtractGivesExactValuesAndSecondsSinceTheStart) {
  const UlogFile f = ParseStrict(testing::EveryMessageKindLog().bytes(), "all.ulg");
  const SignalSamples q2 = Extract(f, "sensor.q[2]");
  EXPECT_EQ(q2.name, "sensor.q[2]");
  EXPECT_EQ(q2.t_s, (std::vector<double>{0.1, 0.2, 0.3}));
  EXPECT_EQ(q2.values, (std::vector<double>{2.0, 2.5, 3.0}));
  EXPECT_EQ(Extract(f, "sensor.i64").values[1], static_cast<double>(-9000000000000000000LL + 1));
  EXPECT_EQ(Extract(f, "sensor.mags[1].y").values[2], 23.0);
  EXPECT_EQ(Extract(f, "sensor.wheels[0].rpm").values, (std::vector<double>{1000, 1001, 1002}));
  const SignalSamples m1 = Extract(f, "motor/1.thrust[0]");
  EXPECT_EQ(m1.values, (std::vector<double>{0.75, 1.0}));
  EXPECT_DOUBLE_EQ(m1.t_s[0], 0.1007);
  EXPECT_EQ(Extract(f, "motor.thrust[1]").values, (std::vector<double>{0.25, 0.5}));
}

TEST(UlogSignals, AnUnknownNameNamesTheNearestOnes) {
  const UlogFile f = ParseStrict(testing::EveryMessageKindLog().bytes(), "all.ulg");
  for (const char* bad : {"sensor.q[7]", "sensor.timestamp", "sensor.label", "motor/2.thrust[0]",
                          "sensor", "", "sensor.acel.x"}) {
    SCOPED_TRACE(bad);
    try {
      Extract(f, bad);
      ADD_FAILURE() << "no throw";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("no signal '" + std::string(bad) + "' in all.ulg; nearest: "),
                std::string::npos)
          << what;
    }
  }
  try {
    Extract(f, "sensor.acel.x");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("nearest: sensor.accel.x,"), std::string::npos)
        << e.what();
  }
}

TEST(UlogSignals, TimesThatGoBackwardsAreDroppedAndCounted) {
  // 0.05 s comes after 0.06 s: dropped. Equal times are kept, in file order.
  const UlogFile f = TwoRatesLog({kStartUs + 10'000, kStartUs + 20'000, kStartUs + 60'000,
                                  kStartUs + 50'000, kStartUs + 60'000, kStartUs + 70'000});
  const SignalSamples a = Extract(f, "a.v");
  EXPECT_EQ(a.out_of_order, 1u);
  EXPECT_EQ(a.t_s, (std::vector<double>{0.01, 0.02, 0.06, 0.06, 0.07}));
  EXPECT_DOUBLE_EQ(a.values[3], 0.12);
  const auto signals = ListSignals(f);
  EXPECT_EQ(signals[0].name, "a.v");
  EXPECT_EQ(signals[0].samples, 5u);
  EXPECT_EQ(signals[0].out_of_order, 1u);
  // Intervals of distinct times: 10, 40, 10 ms → median 10 ms.
  EXPECT_DOUBLE_EQ(signals[0].median_rate_hz, 100.0);
  EXPECT_DOUBLE_EQ(signals[0].mean_rate_hz, 4 / 0.06);
  // Resampling sees the kept samples only: at 0.05 s, between 0.02 (0.04) and 0.06 (0.12).
  const ResampledSignals r = Resample(f, {"a.v"}, 100.0, 10);
  EXPECT_EQ(r.out_of_order, std::vector<std::size_t>{1});
  ASSERT_EQ(r.t_s.size(), 7u);
  EXPECT_NEAR(r.columns[0][4], 0.10, 1e-12);
}

// Issue 61: one flipped byte in a timestamp (2^56 µs ahead) drops that sample alone, counted;
// the rest of the signal is read and resampled as before.
TEST(UlogSignals, ALoneLeapAheadInTimeIsDroppedNotTheRestOfTheLog) {
  std::vector<std::uint64_t> times;
  for (std::uint64_t i = 0; i <= 100; ++i) times.push_back(kStartUs + 10'000 * i);
  times[40] |= std::uint64_t{1} << 56;
  const UlogFile f = TwoRatesLog(times);
  const SignalSamples a = Extract(f, "a.v");
  EXPECT_EQ(a.out_of_order, 1u);
  EXPECT_EQ(a.t_s.size(), 100u);
  const ResampledSignals r = Resample(f, {"a.v", "b.v"}, 0.0, 3);
  EXPECT_NEAR(r.t_s.back(), 0.983, 1e-9);  // b's 50 Hz grid to a's end, not 7.2e10 s
  EXPECT_EQ(r.out_of_order[0], 1u);
  // The leap as the very last sample is dropped too.
  times[40] = kStartUs + 400'000;
  times.back() |= std::uint64_t{1} << 56;
  EXPECT_EQ(Extract(TwoRatesLog(times), "a.v").t_s.size(), 100u);
}

TEST(UlogSignals, SamplesBeforeTheStartHaveNegativeTimes) {
  UlogWriter w(1, 5'000'000);
  w.Format("a:uint64_t timestamp;uint8_t v;").Subscribe(0, 0, "a");
  w.Data(0, Payload().Put(std::uint64_t{0}).Put(std::uint8_t{1}));
  w.Data(0, Payload().Put(std::uint64_t{5'000'001}).Put(std::uint8_t{2}));
  const SignalSamples s = Extract(ParseStrict(w.bytes(), "x"), "a.v");
  EXPECT_EQ(s.t_s, (std::vector<double>{-5.0, 1e-6}));
}

TEST(UlogSignals, ResampleInterpolatesEachSignalOnTheOverlap) {
  const UlogFile f = TwoRatesLog();
  const ResampledSignals slowest = Resample(f, {"b.v", "a.v", "b.n"}, 0.0, 1);
  EXPECT_NEAR(slowest.rate_hz, 50.0, 1e-9);  // b's, the slowest: every signal fills it
  EXPECT_TRUE(slowest.rate_chosen);
  EXPECT_EQ(slowest.gap_cells, (std::vector<std::size_t>{0, 0, 0}));
  const ResampledSignals r = Resample(f, {"b.v", "a.v", "b.n"}, 100.0, 1);
  EXPECT_FALSE(r.rate_chosen);
  // From b's first sample (3 ms) to a's last (1 s): 100 points at 3, 13, … 993 ms.
  ASSERT_EQ(r.t_s.size(), 100u);
  EXPECT_DOUBLE_EQ(r.t_s.front(), 0.003);
  EXPECT_NEAR(r.t_s.back(), 0.993, 1e-12);
  ASSERT_EQ(r.columns.size(), 3u);
  EXPECT_EQ(r.names, (std::vector<std::string>{"b.v", "a.v", "b.n"}));
  for (std::size_t i = 0; i < r.t_s.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_NEAR(r.columns[1][i], 2.0 * r.t_s[i], 1e-12);  // linear data interpolates exactly
    EXPECT_NEAR(r.columns[0][i], 1.0 - r.t_s[i], 1e-6);   // float samples
    EXPECT_DOUBLE_EQ(r.columns[2][i], 0.5 * static_cast<double>(i));
  }
  EXPECT_EQ(r.gap_cells, (std::vector<std::size_t>{0, 0, 0}));
  EXPECT_EQ(r.out_of_order, (std::vector<std::size_t>{0, 0, 0}));
  // b's samples are 20 ms apart, two grid periods: with max_gap 0 that is too far, except where
  // a grid time falls on a sample.
  const ResampledSignals strict = Resample(f, {"b.n"}, 100.0, 0);
  ASSERT_EQ(strict.t_s.size(), 101u);  // b alone: 3 ms to 1003 ms
  EXPECT_EQ(strict.columns[0][0], 0.0);
  EXPECT_TRUE(std::isnan(strict.columns[0][1]));
  EXPECT_EQ(strict.columns[0][2], 1.0);
  EXPECT_EQ(strict.gap_cells[0], 50u);
}

TEST(UlogSignals, NeighboursFurtherThanMaxGapPlusOnePeriodsMakeNaN) {
  // a at 100 Hz with the samples from 0.50 s to 0.55 s missing: 0.49 and 0.56 are 7 periods apart.
  std::vector<std::uint64_t> times;
  for (std::uint64_t i = 0; i <= 100; ++i)
    if (i < 50 || i > 55) times.push_back(kStartUs + 10'000 * i);
  const UlogFile f = TwoRatesLog(times);
  for (const int max_gap : {5, 6}) {
    SCOPED_TRACE(max_gap);
    const ResampledSignals r = Resample(f, {"a.v"}, 100.0, max_gap);
    ASSERT_EQ(r.t_s.size(), 101u);
    for (std::size_t i = 0; i < r.t_s.size(); ++i) {
      const bool in_gap = i >= 50 && i <= 55;
      if (in_gap && max_gap == 5)
        EXPECT_TRUE(std::isnan(r.columns[0][i])) << i;
      else
        EXPECT_NEAR(r.columns[0][i], 0.02 * static_cast<double>(i), 1e-12) << i;
    }
    EXPECT_EQ(r.gap_cells[0], max_gap == 5 ? 6u : 0u);
  }
  // A slower grid: its own periods count. At 20 Hz the 70 ms gap is 1.4 periods.
  EXPECT_EQ(Resample(f, {"a.v"}, 20.0, 0).gap_cells[0], 2u);
  EXPECT_EQ(Resample(f, {"a.v"}, 20.0, 1).gap_cells[0], 0u);
}

TEST(UlogSignals, ResampleRefusesWhatItCannotDo) {
  const UlogFile f = TwoRatesLog();
  EXPECT_THROW(Resample(f, {}, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.v", "a.v"}, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.x"}, 0.0, 0), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.v"}, -1.0, 0), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.v"}, std::nan(""), 0), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.v"}, 10.0, -1), std::invalid_argument);
  EXPECT_THROW(Resample(f, {"a.v"}, 1e12, 0), std::invalid_argument);  // too many cells
  // Spans that do not overlap.
  const UlogFile apart = TwoRatesLog({kStartUs + 2'000'000, kStartUs + 3'000'000});
  EXPECT_THROW(Resample(apart, {"a.v", "b.v"}, 0.0, 0), std::invalid_argument);
  // One sample: no rate of its own, but a grid of one point when the rate is given.
  const UlogFile single = TwoRatesLog({kStartUs + 500'000});
  EXPECT_THROW(Resample(single, {"a.v"}, 0.0, 0), std::invalid_argument);
  const ResampledSignals one = Resample(single, {"a.v"}, 10.0, 0);
  EXPECT_EQ(one.t_s, std::vector<double>{0.5});
  EXPECT_EQ(one.columns[0], std::vector<double>{1.0});
  // A topic without samples.
  UlogWriter w(1, kStartUs);
  w.Format("a:uint64_t timestamp;double v;").Subscribe(0, 0, "a");
  const UlogFile empty = ParseStrict(w.bytes(), "empty.ulg");
  EXPECT_TRUE(ListSignals(empty).empty());
  try {
    Extract(empty, "a.v");
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("topic 'a' is subscribed but has no samples"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(Resample(empty, {"a.v"}, 10.0, 0), std::invalid_argument);
}

TEST(UlogSignals, AHostileFileCostsNoMoreThanItsBytes) {
  // 60001 fields a format, in 256 instances, without data: one layout, no signal names.
  UlogWriter w(1);
  w.Format("one:uint8_t v;").Format("big:uint64_t timestamp;one[60000] o;");
  for (int i = 0; i < 256; ++i)
    w.Subscribe(static_cast<std::uint8_t>(i), static_cast<std::uint16_t>(i), "big");
  const UlogFile f = ParseStrict(w.bytes(), "hostile.ulg");
  EXPECT_EQ(f.subscriptions.size(), 256u);
  EXPECT_EQ(f.subscriptions[0].layout, f.subscriptions[255].layout);
  EXPECT_TRUE(ListSignals(f).empty());
  EXPECT_THROW(Extract(f, "big/7.o[5].v"), std::invalid_argument);
  // Distinct formats that large stop at the field budget, as damage.
  UlogWriter many(1);
  many.Format("one:uint8_t v;");
  for (int i = 0; i < 20; ++i) {
    const std::string name = "big" + std::to_string(i);
    many.Format(name + ":uint64_t timestamp;one[60000] o;")
        .Subscribe(0, static_cast<std::uint16_t>(i), name);
  }
  const UlogFile g = Parse(many.bytes(), "hostile.ulg");
  EXPECT_FALSE(g.complete());
  EXPECT_NE(g.problem.find("more fields than this reader holds"), std::string::npos) << g.problem;
  EXPECT_EQ(g.subscriptions.size(), 16u);  // 16 x 60001 fields fit in the budget of a million
}

TEST(UlogSignals, ResampledSignalsMakeATable) {
  const ResampledSignals r = Resample(TwoRatesLog(), {"a.v", "b.n"}, 50.0, 0);
  std::vector<std::string> names = {"t_s"};
  names.insert(names.end(), r.names.begin(), r.names.end());
  std::vector<std::vector<double>> columns = {r.t_s};
  columns.insert(columns.end(), r.columns.begin(), r.columns.end());
  const io::CsvTable t = io::CsvTable::FromColumns("two_rates.ulg", names, columns);
  EXPECT_EQ(t.names(), names);
  EXPECT_EQ(t.rows(), r.t_s.size());
  EXPECT_EQ(t.Column("b.n")[1], 1.0);
  EXPECT_EQ(t.source(), "two_rates.ulg");
  EXPECT_THROW(io::CsvTable::FromColumns("x", {"a", "a"}, {{1}, {2}}), io::CsvError);
  EXPECT_THROW(io::CsvTable::FromColumns("x", {"a", "b"}, {{1}, {2, 3}}), io::CsvError);
  EXPECT_THROW(io::CsvTable::FromColumns("x", {"a"}, {{1}, {2}}), io::CsvError);
  EXPECT_THROW(io::CsvTable::FromColumns("x", {""}, {{1}}), io::CsvError);
  EXPECT_EQ(io::CsvTable::FromColumns("x", {}, {}).rows(), 0u);
}

}  // namespace
}  // namespace odonata::ulog

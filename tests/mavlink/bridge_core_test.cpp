// The bridge's core (mavlink/bridge_core.hpp) on frames encoded apart (mavlink_test_support.hpp),
// fed with arrival times: its grid samples equal timeseries::Resample of the same samples on the
// same grid, however the bytes are split; dropped and foreign frames never reach a value; a field
// never sent is named; a long silence is a counted gap. And on an ArduSub vehicle's real .tlog,
// replayed at its record times: what odonata-fit's reading (mavlink::Extract, the same resampler)
// gives, but for the counted gaps.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "mavlink/bridge_core.hpp"
#include "mavlink/frame_decoder.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"
#include "mavlink_test_support.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::mavlink {
namespace {

struct BridgeTimedFrame {
  double t_s = 0.0;  // arrival
  std::string bytes;
};

// ATTITUDE at 50 Hz with jittered arrivals (pitch, pitchspeed), SERVO_OUTPUT_RAW at 20 Hz
// (servo3_raw), HEARTBEAT at 2 Hz (base_mode, a held uint8), all from 1:1, for `seconds`; and
// the same samples as TimedSignals in that field order.
struct BridgeFlight {
  std::vector<BridgeTimedFrame> frames;
  std::vector<timeseries::TimedSignal> signals;
};

const std::vector<std::string> kBridgeFlightFields = {
    "ATTITUDE.pitch", "ATTITUDE.pitchspeed", "SERVO_OUTPUT_RAW.servo3_raw", "HEARTBEAT.base_mode"};

BridgeFlight BridgeMakeFlight(double seconds) {
  BridgeFlight f;
  f.signals.resize(4);
  for (std::size_t i = 0; i < 4; ++i) f.signals[i].name = kBridgeFlightFields[i];
  f.signals[3].interpolation = timeseries::Interpolation::kHold;
  std::uint8_t seq = 0;
  for (int i = 0; 0.02 * i < seconds; ++i) {
    const double t = 0.02 * i + 0.004 * ((i * 37) % 11) / 11.0;
    const float pitch = static_cast<float>(0.3 * std::sin(1.7 * t));
    const float rate = static_cast<float>(0.5 * std::cos(2.3 * t));
    f.frames.push_back(
        {t, test_support::AttitudeFrame(seq++, static_cast<std::uint32_t>(20 * i), pitch, rate)});
    f.signals[0].t_s.push_back(t);
    f.signals[0].values.push_back(static_cast<double>(pitch));
    f.signals[1].t_s.push_back(t);
    f.signals[1].values.push_back(static_cast<double>(rate));
  }
  for (int j = 0; 0.013 + 0.05 * j < seconds; ++j) {
    const double t = 0.013 + 0.05 * j;
    const unsigned servo3 = 1500u + static_cast<unsigned>(std::lround(200.0 + 200.0 * std::sin(t)));
    test_support::FrameSpec spec;
    spec.msgid = 36;
    spec.seq = seq++;
    spec.payload = test_support::ServoPayload(static_cast<std::uint32_t>(50'000 * j), 0,
                                              {1500, 1500, servo3, 1500, 1500, 1500, 1500, 1500});
    f.frames.push_back({t, test_support::EncodeFrame(spec)});
    f.signals[2].t_s.push_back(t);
    f.signals[2].values.push_back(static_cast<double>(servo3));
  }
  for (int h = 0; 0.007 + 0.5 * h < seconds; ++h) {
    const double t = 0.007 + 0.5 * h;
    const unsigned base_mode = h % 2 == 0 ? 81u : 209u;
    test_support::FrameSpec spec;
    spec.msgid = 0;
    spec.seq = seq++;
    spec.payload = test_support::HeartbeatPayload(19, 12, base_mode);
    f.frames.push_back({t, test_support::EncodeFrame(spec)});
    f.signals[3].t_s.push_back(t);
    f.signals[3].values.push_back(static_cast<double>(base_mode));
  }
  std::stable_sort(
      f.frames.begin(), f.frames.end(),
      [](const BridgeTimedFrame& a, const BridgeTimedFrame& b) { return a.t_s < b.t_s; });
  return f;
}

std::vector<GridSample> BridgeFeedFrames(BridgeCore& core,
                                         const std::vector<BridgeTimedFrame>& frames) {
  for (const BridgeTimedFrame& f : frames) core.Feed(f.bytes, f.t_s);
  return core.TakeSamples();
}

// Every sample the bridge made equals the grid's, NaN for NaN, to 1e-12.
void BridgeExpectOnGrid(const std::vector<GridSample>& got, const timeseries::UniformGrid& want) {
  ASSERT_LE(got.size(), want.t_s.size());
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_EQ(got[i].k, static_cast<std::int64_t>(i));
    EXPECT_NEAR(got[i].t_s, want.t_s[i], 1e-12);
    ASSERT_EQ(got[i].values.size(), want.columns.size());
    for (std::size_t c = 0; c < want.columns.size(); ++c) {
      if (std::isnan(want.columns[c][i])) {
        EXPECT_TRUE(std::isnan(got[i].values[c])) << "sample " << i << ", field " << c;
      } else {
        EXPECT_NEAR(got[i].values[c], want.columns[c][i], 1e-12)
            << "sample " << i << ", field " << c;
      }
    }
  }
}

// The same samples, bit for bit (NaN for NaN).
void BridgeExpectSameSamples(const std::vector<GridSample>& a, const std::vector<GridSample>& b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].k, b[i].k);
    EXPECT_EQ(a[i].t_s, b[i].t_s);
    ASSERT_EQ(a[i].values.size(), b[i].values.size());
    for (std::size_t c = 0; c < a[i].values.size(); ++c) {
      if (std::isnan(a[i].values[c])) {
        EXPECT_TRUE(std::isnan(b[i].values[c])) << "sample " << i;
      } else {
        EXPECT_EQ(a[i].values[c], b[i].values[c]) << "sample " << i;
      }
    }
  }
}

timeseries::UniformGrid BridgeResampled(const std::vector<timeseries::TimedSignal>& signals,
                                        double rate_hz, double from_s, int max_gap) {
  timeseries::GridOptions o;
  o.rate_hz = rate_hz;
  o.max_gap = max_gap;
  o.from_s = from_s;
  return timeseries::Resample(signals, o);
}

// What ParseFieldSelector says of `text`; empty when it takes it.
std::string BridgeSelectorError(const std::string& text) {
  try {
    ParseFieldSelector(text);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(BridgeCore, GivenRateEqualsResample) {
  const BridgeFlight flight = BridgeMakeFlight(4.0);
  BridgeOptions o;
  o.fields = kBridgeFlightFields;
  o.rate_hz = 25.0;
  BridgeCore core(o);
  const std::vector<GridSample> got = BridgeFeedFrames(core, flight.frames);
  EXPECT_DOUBLE_EQ(core.t0_s(), 0.013);  // the latest first sample: SERVO_OUTPUT_RAW's
  EXPECT_GE(got.size(), 80u);            // up to HEARTBEAT's last sample, 3.507 s
  BridgeExpectOnGrid(got, BridgeResampled(flight.signals, 25.0, core.t0_s(), o.max_gap));
  EXPECT_EQ(core.grid_samples(), got.size());
  EXPECT_EQ(core.counters().frames_ok, flight.frames.size());
  EXPECT_TRUE(core.TakeSamples().empty());  // each sample once
}

TEST(BridgeCore, ChosenRateIsTheSlowestFieldsAndEqualsResample) {
  const BridgeFlight flight = BridgeMakeFlight(4.0);
  BridgeOptions o;
  o.fields = kBridgeFlightFields;
  BridgeCore core(o);
  EXPECT_EQ(core.rate_hz(), 0.0);
  const std::vector<GridSample> got = BridgeFeedFrames(core, flight.frames);
  EXPECT_NEAR(core.rate_hz(), 20.0, 1e-6);  // SERVO_OUTPUT_RAW's, not HEARTBEAT's (held)
  EXPECT_NE(core.rate_note().find("SERVO_OUTPUT_RAW.servo3_raw"), std::string::npos)
      << core.rate_note();
  EXPECT_GE(got.size(), 60u);
  BridgeExpectOnGrid(got, BridgeResampled(flight.signals, core.rate_hz(), core.t0_s(), o.max_gap));
}

TEST(BridgeCore, BytesSplitAnywhereGiveTheSameSamples) {
  const BridgeFlight flight = BridgeMakeFlight(1.5);
  BridgeOptions o;
  o.fields = kBridgeFlightFields;
  o.rate_hz = 30.0;
  BridgeCore whole(o);
  const std::vector<GridSample> want = BridgeFeedFrames(whole, flight.frames);
  ASSERT_GT(want.size(), 20u);
  BridgeCore bytewise(o);
  for (const BridgeTimedFrame& f : flight.frames)
    for (const char& c : f.bytes) bytewise.Feed(std::string_view(&c, 1), f.t_s);
  BridgeExpectSameSamples(bytewise.TakeSamples(), want);
}

TEST(BridgeCore, DroppedAndForeignFramesAreCountedAndNeverValues) {
  BridgeOptions o;
  o.fields = {"ATTITUDE.pitch"};  // locks onto 1:1, the first sender heard
  o.rate_hz = 10.0;
  BridgeCore clean(o);
  BridgeCore noisy(o);
  std::vector<BridgeTimedFrame> good;
  std::vector<BridgeTimedFrame> all;
  for (int i = 0; i < 30; ++i) {
    const double t = 0.1 * i;
    const std::string frame = test_support::AttitudeFrame(static_cast<std::uint8_t>(i),
                                                          static_cast<std::uint32_t>(100 * i),
                                                          static_cast<float>(0.01 * i), 0.0f);
    good.push_back({t, frame});
    all.push_back({t, frame});
    if (i % 3 == 0) {  // a corrupted ATTITUDE saying 100
      std::string bad = test_support::AttitudeFrame(0, 0, 100.0f, 0.0f);
      bad[12] = static_cast<char>(bad[12] ^ 0x40);
      all.push_back({t + 0.03, bad});
    } else if (i % 3 == 1) {  // a message the table does not know
      all.push_back({t + 0.03, test_support::UnknownFrame(static_cast<std::uint8_t>(i))});
    } else {  // another vehicle's ATTITUDE saying 100
      all.push_back({t + 0.03, test_support::AttitudeFrame(static_cast<std::uint8_t>(i), 0, 100.0f,
                                                           0.0f, 2, 1)});
    }
  }
  const std::vector<GridSample> want = BridgeFeedFrames(clean, good);
  const std::vector<GridSample> got = BridgeFeedFrames(noisy, all);
  ASSERT_GT(got.size(), 20u);
  BridgeExpectSameSamples(got, want);
  for (const GridSample& s : got) {
    EXPECT_LT(std::abs(s.values[0]), 1.0) << "t " << s.t_s;
  }
  EXPECT_EQ(noisy.counters().bad_crc, 10u);
  EXPECT_EQ(noisy.counters().unknown_message, 10u);
  EXPECT_EQ(noisy.counters().frames_ok, 40u);  // 30 of 1:1, 10 of 2:1
  const nlohmann::json summary = noisy.Summary();
  EXPECT_EQ(summary["frames"]["other_sender"], 10);
  EXPECT_EQ(summary["fields"][0]["sender"], "1:1");
  EXPECT_EQ(summary["fields"][0]["samples"], 30);

  // Named with its sender, another vehicle's frames are foreign from the start.
  BridgeOptions o2 = o;
  o2.fields = {"ATTITUDE@1:1.pitch"};
  BridgeCore named(o2);
  std::vector<BridgeTimedFrame> foreign_first = all;
  foreign_first.insert(
      foreign_first.begin(),
      BridgeTimedFrame{-0.05, test_support::AttitudeFrame(0, 0, 100.0f, 0.0f, 2, 1)});
  BridgeExpectSameSamples(BridgeFeedFrames(named, foreign_first), want);
  EXPECT_EQ(named.Summary()["frames"]["other_sender"], 11);
}

TEST(BridgeCore, AFieldNeverSentIsNamedAfterTheSilence) {
  BridgeOptions o;
  o.fields = {"ATTITUDE.pitch", "SERVO_OUTPUT_RAW.servo1_raw"};
  o.rate_hz = 10.0;
  o.silence_s = 3.0;
  BridgeCore core(o);
  EXPECT_TRUE(core.Silent(100.0).empty());  // nothing fed yet
  for (int i = 0; i < 40; ++i)
    core.Feed(test_support::AttitudeFrame(static_cast<std::uint8_t>(i), 0, 0.1f, 0.0f), 0.1 * i);
  EXPECT_TRUE(core.Silent(2.5).empty());
  EXPECT_EQ(core.Silent(3.5), std::vector<std::string>{"SERVO_OUTPUT_RAW.servo1_raw"});
  EXPECT_EQ(core.Silent(7.5),
            (std::vector<std::string>{"ATTITUDE.pitch", "SERVO_OUTPUT_RAW.servo1_raw"}));
  EXPECT_TRUE(core.TakeSamples().empty());  // no grid without every field
  EXPECT_TRUE(std::isnan(core.t0_s()));
  EXPECT_TRUE(core.Summary()["grid"]["t0_s"].is_null());
}

TEST(BridgeCore, ALongSilenceIsAGapThenSamplesResume) {
  BridgeOptions o;
  o.fields = {"ATTITUDE.pitch"};
  o.rate_hz = 10.0;
  o.max_gap = 3;
  BridgeCore core(o);
  timeseries::TimedSignal pitch;
  pitch.name = "ATTITUDE.pitch";
  std::vector<BridgeTimedFrame> frames;
  for (int i = 0; i <= 40; ++i) {
    if (i > 10 && i < 30) continue;  // silent from 1.0 s to 3.0 s
    const double t = static_cast<double>(i) / 10.0;
    const float v = static_cast<float>(0.02 * i);
    frames.push_back({t, test_support::AttitudeFrame(static_cast<std::uint8_t>(i), 0, v, 0.0f)});
    pitch.t_s.push_back(t);
    pitch.values.push_back(static_cast<double>(v));
  }
  const std::vector<GridSample> got = BridgeFeedFrames(core, frames);
  ASSERT_EQ(got.size(), 40u);  // 0.0 to 3.9 s: 4.0 s waits for a later sample
  std::size_t gaps = 0;
  for (const GridSample& s : got) {
    if (s.gap()) ++gaps;
  }
  EXPECT_EQ(gaps, 19u);  // 1.1 s to 2.9 s
  EXPECT_EQ(core.gap_samples(), gaps);
  EXPECT_FALSE(got[10].gap());
  for (std::size_t k = 30; k < got.size(); ++k) {
    EXPECT_FALSE(got[k].gap()) << k;
  }
  BridgeExpectOnGrid(got, BridgeResampled({pitch}, 10.0, core.t0_s(), o.max_gap));
}

TEST(BridgeCore, FieldSelectorsAndTheirMistakes) {
  const FieldSelector plain = ParseFieldSelector("ATTITUDE.pitchspeed");
  EXPECT_EQ(plain.message, "ATTITUDE");
  EXPECT_EQ(plain.field, "pitchspeed");
  EXPECT_FALSE(plain.sysid.has_value());
  const FieldSelector element = ParseFieldSelector("ACTUATOR_OUTPUT_STATUS.actuator[1]");
  EXPECT_EQ(element.message, "ACTUATOR_OUTPUT_STATUS");
  EXPECT_EQ(element.field, "actuator[1]");
  const FieldSelector sender = ParseFieldSelector("ATTITUDE@1:190.pitch");
  EXPECT_EQ(sender.name, "ATTITUDE@1:190.pitch");
  EXPECT_EQ(sender.message, "ATTITUDE");
  EXPECT_EQ(sender.field, "pitch");
  ASSERT_TRUE(sender.sysid.has_value() && sender.compid.has_value());
  EXPECT_EQ(*sender.sysid, 1);
  EXPECT_EQ(*sender.compid, 190);

  EXPECT_NE(BridgeSelectorError("ATTITUDE.pitchsped").find("ATTITUDE.pitchspeed"),
            std::string::npos);
  EXPECT_NE(BridgeSelectorError("ATTITUD.pitch").find("nearest: ATTITUDE"), std::string::npos);
  EXPECT_NE(BridgeSelectorError("ACTUATOR_OUTPUT_STATUS.actuator").find("actuator[0]"),
            std::string::npos);
  EXPECT_FALSE(BridgeSelectorError("ATTITUDE").empty());
  EXPECT_FALSE(BridgeSelectorError("ATTITUDE@1.pitch").empty());
  EXPECT_FALSE(BridgeSelectorError("ATTITUDE@1:256.pitch").empty());
  BridgeOptions twice;
  twice.fields = {"ATTITUDE.pitch", "ATTITUDE.pitch"};
  EXPECT_THROW(BridgeCore{twice}, std::invalid_argument);
}

#ifdef ODONATA_MAVLINK_DIR

// The ArduSub .tlog replayed record by record at its own times (seconds from its first record,
// as tlog_signals times them) equals Extract + Resample of the same signals on the same grid,
// but for the bridge's gaps, which it counts.
TEST(BridgeCoreRealFile, ReplayedTlogEqualsTheLogsReading) {
  const std::string path = std::string(ODONATA_MAVLINK_DIR) + "/ardusub_small.tlog";
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << path;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const TlogFile file = Read(path);
  ASSERT_TRUE(file.complete()) << file.problem;

  BridgeOptions o;
  o.fields = {"ATTITUDE.pitchspeed", "ATTITUDE.roll"};
  o.rate_hz = 20.0;
  BridgeCore core(o);
  const std::string_view all(bytes);
  std::size_t at = 0;
  std::size_t records = 0;
  Frame frame;
  while (at + kTlogTimestampSize < all.size()) {
    std::uint64_t t_us = 0;
    for (std::size_t i = 0; i < kTlogTimestampSize; ++i)
      t_us = t_us << 8 | static_cast<std::uint8_t>(all[at + i]);
    const std::string_view rest = all.substr(at + kTlogTimestampSize);
    const FrameRead r = ReadFrame(rest, frame);
    ASSERT_NE(r.status, FrameStatus::kNoFrame) << "at byte " << at;
    ASSERT_NE(r.status, FrameStatus::kNeedMore) << "at byte " << at;
    const std::uint64_t zero_us = file.first_time_us;
    const double t_s = t_us >= zero_us ? static_cast<double>(t_us - zero_us) / 1e6
                                       : -static_cast<double>(zero_us - t_us) / 1e6;
    core.Feed(rest.substr(0, r.size), t_s);
    at += kTlogTimestampSize + r.size;
    ++records;
  }
  EXPECT_EQ(records, file.records);
  const std::vector<GridSample> got = core.TakeSamples();

  const MessageSeries* main = file.FindMain("ATTITUDE");
  ASSERT_NE(main, nullptr);
  EXPECT_EQ(core.Summary()["fields"][0]["sender"], main->sender());
  const std::vector<timeseries::TimedSignal> signals = {Extract(file, "ATTITUDE.pitchspeed"),
                                                        Extract(file, "ATTITUDE.roll")};
  const timeseries::UniformGrid want = BridgeResampled(signals, 20.0, core.t0_s(), o.max_gap);
  ASSERT_LE(got.size(), want.t_s.size());
  EXPECT_GE(got.size() + 5, want.t_s.size());  // all but the last, awaiting a later frame
  std::size_t gaps = 0;
  for (std::size_t i = 0; i < got.size(); ++i) {
    EXPECT_NEAR(got[i].t_s, want.t_s[i], 1e-12);
    if (got[i].gap()) {
      ++gaps;
      continue;
    }
    for (std::size_t c = 0; c < 2; ++c) {
      EXPECT_NEAR(got[i].values[c], want.columns[c][i], 1e-12) << "sample " << i << ", " << c;
    }
  }
  EXPECT_EQ(gaps, core.gap_samples());
  EXPECT_EQ(core.counters().bad_crc, 0u);
}

#endif  // ODONATA_MAVLINK_DIR

}  // namespace
}  // namespace odonata::mavlink

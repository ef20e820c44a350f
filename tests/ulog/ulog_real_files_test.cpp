// Real PX4 flight logs (shared/px4-ulog, from PX4's pyulog test files): read whole, sample counts
// against an independent walk of the message headers, and values against numbers decoded outside
// this reader (Python's struct module on the same bytes; the script is described at each number).
// Registered only when the folder exists (tests/ulog/CMakeLists.txt sets ODONATA_PX4_ULOG_DIR).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <iterator>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

#ifndef ODONATA_PX4_ULOG_DIR
#error "ODONATA_PX4_ULOG_DIR must name the folder of the PX4 sample logs"
#endif

namespace odonata::ulog {
namespace {

std::string PathOf(const char* file) { return std::string(ODONATA_PX4_ULOG_DIR) + "/" + file; }

std::string Bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The least a reader must do, written apart from the one under test: message headers only.
struct HeaderWalk {
  std::map<std::uint16_t, std::size_t> data_per_msg_id;
  std::map<std::uint16_t, std::pair<std::string, int>> topics;  // msg_id -> (topic, multi_id)
  std::map<std::uint16_t, std::size_t> first_data_offset;
  std::size_t messages_from = 0;  // messages at or after `from`
  std::size_t end = 0;
};

HeaderWalk Walk(const std::string& b, std::size_t from = ~std::size_t{0}) {
  HeaderWalk w;
  const auto u8 = [&](std::size_t i) {
    return static_cast<unsigned>(static_cast<unsigned char>(b[i]));
  };
  std::size_t pos = 16;
  while (pos + 3 <= b.size()) {
    const std::size_t size = u8(pos) | u8(pos + 1) << 8;
    const char type = b[pos + 2];
    if (pos + 3 + size > b.size()) break;
    if (pos >= from) ++w.messages_from;
    if (type == 'A') {
      const std::uint16_t id = static_cast<std::uint16_t>(u8(pos + 4) | u8(pos + 5) << 8);
      w.topics[id] = {b.substr(pos + 6, size - 3), static_cast<int>(u8(pos + 3))};
    } else if (type == 'D') {
      const std::uint16_t id = static_cast<std::uint16_t>(u8(pos + 3) | u8(pos + 4) << 8);
      ++w.data_per_msg_id[id];
      w.first_data_offset.emplace(id, pos);
    }
    pos += 3 + size;
  }
  w.end = pos;
  return w;
}

void ExpectCountsMatchTheWalk(const UlogFile& f, const HeaderWalk& w) {
  EXPECT_EQ(w.end, f.file_size);
  EXPECT_EQ(f.subscriptions.size(), w.topics.size());
  std::size_t data = 0;
  for (const auto& s : f.subscriptions) {
    SCOPED_TRACE(s.topic);
    const auto it = w.data_per_msg_id.find(s.msg_id);
    EXPECT_EQ(s.size(), it == w.data_per_msg_id.end() ? 0u : it->second);
    EXPECT_EQ(w.topics.at(s.msg_id), std::make_pair(s.topic, int{s.multi_id}));
    data += s.size();
  }
  EXPECT_EQ(data, f.MessageCount('D'));
}

const SignalInfo* FindSignal(const std::vector<SignalInfo>& signals, const std::string& name) {
  const auto it = std::find_if(signals.begin(), signals.end(),
                               [&](const SignalInfo& s) { return s.name == name; });
  return it == signals.end() ? nullptr : &*it;
}

TEST(UlogRealFiles, SampleMulticopterVersion0) {
  const std::string path = PathOf("sample.ulg");
  const std::string bytes = Bytes(path);
  const UlogFile f = Read(path);
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_TRUE(f.notes.empty());
  EXPECT_EQ(f.version, 0);
  EXPECT_EQ(f.start_time_us, 112500176u);
  EXPECT_FALSE(f.flags.present);
  const HeaderWalk w = Walk(bytes);
  ExpectCountsMatchTheWalk(f, w);
  EXPECT_EQ(f.subscriptions.size(), 43u);
  EXPECT_EQ(f.message_counts,
            (std::map<char, std::size_t>{
                {'A', 43}, {'D', 64542}, {'F', 103}, {'I', 4}, {'L', 4}, {'O', 4}, {'P', 499}}));
  EXPECT_EQ(f.info.at("ver_hw").Text(), "AUAV_X21");
  EXPECT_EQ(f.info.at("time_ref_utc").Integer(), 0);
  EXPECT_EQ(f.initial_parameters.size(), 493u);
  // The 6 parameter changes in flight, dated by the latest sample before each (Python: the
  // largest D timestamp before byte 2695833).
  ASSERT_EQ(f.changed_parameters.size(), 6u);
  EXPECT_EQ(f.changed_parameters[0].name, "COM_AUTOS_PAR");
  EXPECT_EQ(f.changed_parameters[0].value.Integer(), 0);
  EXPECT_EQ(f.changed_parameters[0].time_us, 158196367u);
  EXPECT_EQ(f.changed_parameters[1].name, "MPC_Z_VEL_MAX_DN");
  EXPECT_EQ(f.changed_parameters[1].value.Number(), 1.0);
  EXPECT_EQ(f.dropouts.size(), 4u);
  EXPECT_EQ(f.dropout_total_ms, 119u);  // 0 + 26 + 31 + 62 ms
  ASSERT_EQ(f.log_messages.size(), 4u);
  EXPECT_EQ(f.log_messages[0].text, "[sensors] no barometer found on /dev/baro0 (2)");

  // vehicle_attitude: its first data message is at byte 36093; its data bytes are the sample.
  const Subscription* att = f.FindTopic("vehicle_attitude");
  ASSERT_NE(att, nullptr);
  ASSERT_EQ(att->size(), 6461u);
  EXPECT_EQ(w.first_data_offset.at(att->msg_id), 36093u);
  EXPECT_EQ(att->layout->logged_size, 36u);  // 40 with the 4 padding bytes the logger leaves out
  EXPECT_TRUE(std::equal(att->data.begin(), att->data.begin() + 36,
                         reinterpret_cast<const std::uint8_t*>(bytes.data()) + 36093 + 5));
  // Python: struct.unpack('<Q3f4f', payload[2:38]) of that message, and of the 1001st.
  EXPECT_EQ(att->timestamps_us[0], 112574307u);
  const std::vector<SignalInfo> signals = ListSignals(f);
  const auto value = [&](const char* name, std::size_t i) { return Extract(f, name).values.at(i); };
  EXPECT_EQ(value("vehicle_attitude.rollspeed", 0), -0.0004259266424924135);
  EXPECT_EQ(value("vehicle_attitude.pitchspeed", 0), 0.000473720021545887);
  EXPECT_EQ(value("vehicle_attitude.yawspeed", 0), 0.0008371851872652769);
  EXPECT_EQ(value("vehicle_attitude.q[0]", 0), 0.9545906186103821);
  EXPECT_EQ(value("vehicle_attitude.q[3]", 0), -0.2910595238208771);
  EXPECT_EQ(value("vehicle_attitude.rollspeed", 1000), 0.0002567277988418937);
  EXPECT_EQ(value("vehicle_attitude.q[3]", 1000), -0.3050015866756439);
  EXPECT_DOUBLE_EQ(Extract(f, "vehicle_attitude.q[3]").t_s.at(1000), (123301507 - 112500176) / 1e6);
  // actuator_controls_0 (Python: '<QQ8f'): first sample and the 2001st.
  EXPECT_EQ(value("actuator_controls_0.timestamp_sample", 0), 112574307.0);
  EXPECT_EQ(value("actuator_controls_0.control[0]", 0), -0.04677823930978775);
  EXPECT_EQ(value("actuator_controls_0.control[1]", 0), -0.09784627705812454);
  EXPECT_EQ(value("actuator_controls_0.control[7]", 0), -1.0);
  EXPECT_EQ(value("actuator_controls_0.control[1]", 2000), -0.10007298737764359);

  // The rates the README gives (≈ 47 Hz and ≈ 94 Hz) are averages; the median intervals are
  // 20.032 ms and 11.999 ms (the attitude alternates 8 ms and 12 ms steps). Python: 1e6 / the
  // median of the positive timestamp differences, and (n - 1) / span.
  const SignalInfo* control = FindSignal(signals, "actuator_controls_0.control[1]");
  ASSERT_NE(control, nullptr);
  EXPECT_EQ(control->type, "float");
  EXPECT_EQ(control->samples, 3269u);
  EXPECT_NEAR(control->median_rate_hz, 49.92012779552716, 1e-9);
  EXPECT_NEAR(control->mean_rate_hz, 47.42663623273685, 1e-9);
  for (const char* name :
       {"vehicle_attitude.rollspeed", "vehicle_attitude.pitchspeed", "vehicle_attitude.yawspeed",
        "vehicle_attitude.q[0]", "vehicle_attitude.q[1]", "vehicle_attitude.q[2]",
        "vehicle_attitude.q[3]"}) {
    const SignalInfo* s = FindSignal(signals, name);
    ASSERT_NE(s, nullptr) << name;
    EXPECT_NEAR(s->median_rate_hz, 83.34027835652971, 1e-9);
    EXPECT_NEAR(s->mean_rate_hz, 93.73948106258607, 1e-9);
    EXPECT_EQ(s->out_of_order, 0u);
  }
  EXPECT_EQ(FindSignal(signals, "vehicle_attitude.timestamp"), nullptr);
  EXPECT_NEAR(FindSignal(signals, "sensor_combined.gyro_rad[2]")->median_rate_hz, 250.0, 1e-9);

  // Resampled at the slower one's median rate (which both fill), over the span both cover.
  const ResampledSignals r =
      Resample(f, {"vehicle_attitude.rollspeed", "actuator_controls_0.control[0]"}, 0.0, 2);
  EXPECT_TRUE(r.rate_chosen);
  EXPECT_NEAR(r.rate_hz, FindSignal(signals, "actuator_controls_0.control[0]")->median_rate_hz,
              1e-6);
  EXPECT_LT(r.rate_hz, 83.0);
  EXPECT_DOUBLE_EQ(r.t_s.front(), (112574774 - 112500176) / 1e6);
  EXPECT_GT(r.t_s.size(), 3000u);
  // The slow command is no gap on its own grid, but for the log's few real dropouts.
  EXPECT_LT(r.gap_cells[1], r.t_s.size() / 100);
}

TEST(UlogRealFiles, SampleVtolPx4_1_11) {
  const std::string path = PathOf("sample_log_small.ulg");
  const UlogFile f = ReadStrict(path);
  EXPECT_EQ(f.version, 1);
  EXPECT_TRUE(f.flags.present);
  EXPECT_FALSE(f.flags.has_appended_data());
  ExpectCountsMatchTheWalk(f, Walk(Bytes(path)));
  EXPECT_EQ(f.subscriptions.size(), 72u);
  EXPECT_EQ(f.MessageCount('D'), 14604u);
  EXPECT_EQ(f.sync_count, 12u);
  EXPECT_EQ(f.dropout_total_ms, 30u);
  EXPECT_EQ(f.info.at("ver_sw_release").Integer(), 0x010b0200);  // v1.11.2, development
  EXPECT_EQ(f.info.at("sys_mcu").Text(), "STM32H7[4|5]xxx, rev. V");
  // Multi-information, joined from its continued messages (Python: lengths summed per key).
  EXPECT_EQ(f.multi_info.at("perf_counter_preflight").at(0).bytes.size(), 5876u);
  EXPECT_EQ(f.multi_info.at("boot_console_output").at(0).bytes.size(), 2191u);
  EXPECT_EQ(f.multi_info.at("perf_top_preflight").at(0).bytes.size(), 2185u);
  EXPECT_EQ(f.multi_info.at("boot_console_output").at(0).Text().rfind("sercon: Registering CDC", 0),
            0u);
  // vehicle_angular_velocity, sample 101 (Python: '<QQ3f').
  const SignalSamples z = Extract(f, "vehicle_angular_velocity.xyz[2]");
  EXPECT_EQ(z.values.size(), 1812u);
  EXPECT_EQ(z.values[100], -0.07649832963943481);
  EXPECT_EQ(Extract(f, "vehicle_angular_velocity.xyz[0]").values[100], -0.00030819803941994905);
  EXPECT_EQ(Extract(f, "vehicle_angular_velocity.timestamp_sample").values[100], 20837511.0);
  EXPECT_DOUBLE_EQ(z.t_s[100], (20837909 - 20309082) / 1e6);
  // A nested format in an array, in the second instance of a topic (Python: the 4th sample's
  // heartbeats[0], '<QBBBB' at byte 40 of its data).
  const std::string hb = "telemetry_status/1.heartbeats[0].";
  EXPECT_EQ(Extract(f, hb + "timestamp").values[3], 21465211.0);
  EXPECT_EQ(Extract(f, hb + "system_id").values[3], 255.0);
  EXPECT_EQ(Extract(f, hb + "component_id").values[3], 190.0);
  EXPECT_EQ(Extract(f, hb + "type").values[3], 6.0);
  EXPECT_EQ(Extract(f, hb + "state").values[3], 4.0);
  EXPECT_EQ(Extract(f, "telemetry_status/1.data_rate").values[3], 1200.0);
  const std::vector<SignalInfo> signals = ListSignals(f);
  const SignalInfo* rate = FindSignal(signals, "vehicle_angular_velocity.xyz[1]");
  ASSERT_NE(rate, nullptr);
  EXPECT_NEAR(rate->mean_rate_hz, 278.67562142278445, 1e-9);  // the README's ≈ 279 Hz
  EXPECT_NE(FindSignal(signals, "sensor_accel/2.x"), nullptr);
  EXPECT_NE(FindSignal(signals, "vehicle_attitude.q[3]"), nullptr);
}

TEST(UlogRealFiles, SampleWithAppendedDataAndTwoInstances) {
  const std::string path = PathOf("sample_appended_multiple.ulg");
  const std::string bytes = Bytes(path);
  const UlogFile f = ReadStrict(path);
  ASSERT_TRUE(f.flags.has_appended_data());
  EXPECT_EQ(f.flags.appended_offsets, (std::array<std::uint64_t, 3>{434369, 451825, 469281}));
  ExpectCountsMatchTheWalk(f, Walk(bytes));
  // Appended after the log was closed: three crash dumps (multi-information), no data samples.
  // The independent walk finds 3 messages from the first offset on.
  EXPECT_EQ(Walk(bytes, 434369).messages_from, 3u);
  EXPECT_EQ(f.appended_messages, 3u);
  ASSERT_EQ(f.multi_info.at("hardfault_plain").size(), 3u);
  for (const auto& [i, time] :
       {std::pair<int, const char*>{0, "00:00:36"}, {1, "00:00:57"}, {2, "00:01:16"}}) {
    const TypedValue& dump = f.multi_info.at("hardfault_plain")[static_cast<std::size_t>(i)];
    EXPECT_EQ(dump.type, "char[17424]");
    EXPECT_EQ(dump.bytes.size(), 17424u);
    EXPECT_EQ(dump.Text().rfind(
                  std::string("[hardfault_log] -- 2000-01-01-") + time + " Begin Fault Log", 0),
              0u)
        << dump.Text().substr(0, 60);
  }
  for (const auto& s : f.subscriptions) EXPECT_EQ(s.first_appended_sample, s.size()) << s.topic;

  // actuator_outputs in two instances (Python: '<QI16f' of each one's first data message).
  const std::vector<SignalInfo> signals = ListSignals(f);
  const SignalInfo* out0 = FindSignal(signals, "actuator_outputs.output[0]");
  const SignalInfo* out1 = FindSignal(signals, "actuator_outputs/1.output[0]");
  ASSERT_NE(out0, nullptr);
  ASSERT_NE(out1, nullptr);
  EXPECT_EQ(out0->samples, 95u);
  EXPECT_EQ(out1->samples, 96u);
  EXPECT_EQ(out1->multi_id, 1);
  EXPECT_EQ(FindSignal(signals, "actuator_outputs/2.output[0]"), nullptr);
  EXPECT_EQ(Extract(f, "actuator_outputs.noutputs").values[0], 8.0);
  EXPECT_EQ(Extract(f, "actuator_outputs.output[3]").values[0], 900.0);
  EXPECT_EQ(Extract(f, "actuator_outputs/1.noutputs").values[0], 4.0);
  EXPECT_EQ(Extract(f, "actuator_outputs/1.output[0]").values[0], 1500.0);
  EXPECT_DOUBLE_EQ(Extract(f, "actuator_outputs/1.output[0]").t_s[0], (12262584 - 12100461) / 1e6);
}

}  // namespace
}  // namespace odonata::ulog

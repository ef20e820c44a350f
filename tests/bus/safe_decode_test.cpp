// SafeDecode over corrupt bytes: every valid message of every type on the project's channels is
// accepted unchanged, and no corruption of its bytes makes decode() allocate what the packet
// cannot hold (the sanitizer build aborts on such an allocation, so running these there is the
// check), whatever the corrupted field.
#include <gtest/gtest.h>
#include <limits>

#include <cstdint>
#include <vector>

#include "bus/safe_decode.hpp"

namespace odonata::bus {
namespace {

template <class Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

odonata::wing_command_t Command() {
  odonata::wing_command_t c{};
  c.seq = 12;
  c.freq_hz[2] = 5.5;
  c.num_excitations = 3;
  c.excitation_names = {"u_roll_rad", "", "noise"};
  c.excitations = {0.1, -0.2, 0.3};
  c.source = "preset:roll/train";
  return c;
}

odonata::prediction_t Prediction() {
  odonata::prediction_t p{};
  p.seq = 3;
  p.num_outputs = 2;
  p.names = {"roll_rad", "pitch_rad"};
  p.measured = {1, 2};
  p.predicted = {3, 4};
  p.free_run = {5, 6};
  p.next = {7, 8};
  p.rules = {9, 10};
  p.max_entropy = {0.1, 0.2};
  p.arx_predicted = {0.3, 0.4};
  p.arx_free_run = {0.5, 0.6};
  p.linear_share = {0.0, 0.25};
  p.learning = 1;
  p.horizon = 20;
  p.num_ahead = 2;
  p.ahead = {0.7, 0.8};
  p.arx_ahead = {0.9, 1.0};
  return p;
}

odonata::accuracy_t Accuracy() {
  odonata::accuracy_t a{};
  a.num_outputs = 2;
  a.names = {"a", "bb"};
  for (auto* v : {&a.window_fit_one_step,     &a.window_vaf_one_step,    &a.window_rmse_one_step,
                  &a.total_fit_one_step,      &a.total_vaf_one_step,     &a.total_rmse_one_step,
                  &a.window_fit_free_run,     &a.window_vaf_free_run,    &a.window_rmse_free_run,
                  &a.total_fit_free_run,      &a.total_vaf_free_run,     &a.total_rmse_free_run,
                  &a.window_fit_one_step_arx, &a.total_fit_one_step_arx, &a.window_fit_free_run_arx,
                  &a.total_fit_free_run_arx,  &a.window_fit_ahead,       &a.total_fit_ahead,
                  &a.window_fit_ahead_arx,    &a.total_fit_ahead_arx})
    *v = {1.5, 2.5};
  a.rules = {3, 4};
  a.gaps = 7;
  return a;
}

odonata::fuzzy_rules_t Rules(int rules, int inputs, int coefficients, int covariance) {
  odonata::fuzzy_rules_t r{};
  r.output_name = "roll_rad";
  r.num_rules = rules;
  r.num_inputs = inputs;
  r.centres.assign(rules, std::vector<double>(inputs, 0.25));
  r.sigmas.assign(rules, std::vector<double>(inputs, 0.5));
  r.output_widths.assign(rules, 1.0);
  r.consequent = "linear";
  r.num_coefficients = coefficients;
  r.coefficients.assign(rules, std::vector<double>(coefficients, -1.0));
  r.covariance_size = covariance;
  r.covariances.assign(rules, std::vector<double>(covariance, 2.0));
  r.entropy_threshold = 0.01;
  r.entropy_measure = "rule";
  r.rls_forgetting = 1.0;
  r.utility_sums.assign(rules, 3.5);
  r.born.assign(rules, 7);
  return r;
}

odonata::model_snapshot_t Snapshot() {
  odonata::model_snapshot_t m{};
  m.seq = 4;
  m.instance = "identifier";
  m.output_lags = 2;
  m.input_lags = 1;
  m.delay = 1;
  m.num_outputs = 2;
  m.outputs = {"roll_rad", "yaw_rad"};
  m.num_inputs = 1;
  m.inputs = {"u_roll_rad"};
  m.num_regressors = 3;
  m.regressor_mid = {0, 1, 2};
  m.regressor_half = {1, 1, 1};
  m.output_mean = {0, 0};
  m.output_std = {1, 1};
  m.output_lower = {-std::numeric_limits<double>::infinity(),
                    -std::numeric_limits<double>::infinity()};
  m.output_upper = {std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};
  m.models = {Rules(3, 3, 4, 16), Rules(1, 3, 1, 0)};
  return m;
}

odonata::heartbeat_t Heartbeat() {
  odonata::heartbeat_t h{};
  h.service = "identifier";
  h.instance = "a";
  h.host = "board-b";
  h.state = "learning";
  h.last_error = "";
  return h;
}

odonata::ack_t Ack() {
  odonata::ack_t a{};
  a.service = "odonata-logger";
  a.instance = "logger";
  a.state_seq = 12;
  return a;
}

odonata::control_t Control() {
  odonata::control_t c{};
  c.sender = "odonata-control";
  c.target = "identifier";
  c.command = odonata::control_t::SAVE_MODEL;
  c.path = "/tmp/model.json";
  return c;
}

odonata::plant_state_t State() {
  odonata::plant_state_t s{};
  s.seq = 5;
  s.attitude_rad[1] = 0.1;
  return s;
}

odonata::beat_state_t BeatState() {
  odonata::beat_state_t b{};
  b.seq = 5;
  b.command_seq = 4;
  b.window_s = 0.19;
  b.velocity_mps[2] = -0.1;
  b.attitude_rad[2] = 4.0;
  b.fz_total_n = 0.39;
  b.applied_amp_rad[3] = 1.05;
  b.u_roll_applied_rad = 0.02;
  b.attitude_hold = 1;
  return b;
}

// Overwrites the 4 bytes at `at` with the big-endian `value`.
void Poke(std::vector<uint8_t>& b, std::size_t at, uint32_t value) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<uint8_t>(value >> (24 - 8 * i));
}

// Every valid message decodes to itself; every truncation is rejected; writing an absurd or
// negative int32 at every offset never crashes (and any count it hits is rejected).
template <class Msg>
void CheckType(const Msg& original) {
  SCOPED_TRACE(Msg::getTypeName());
  const std::vector<uint8_t> good = Encode(original);
  Msg decoded;
  ASSERT_TRUE(CountsFit(&decoded, good.data(), static_cast<int64_t>(good.size())));
  ASSERT_TRUE(SafeDecode(&decoded, good.data(), static_cast<int64_t>(good.size())));
  EXPECT_EQ(Encode(decoded), good);
  for (std::size_t n = 0; n < good.size(); ++n)
    EXPECT_FALSE(SafeDecode(&decoded, good.data(), static_cast<int64_t>(n)))
        << "truncated to " << n;
  EXPECT_FALSE(SafeDecode(&decoded, nullptr, 100));
  for (const uint32_t value : {0x7fffffffu, 0x7f000000u, 0xffffffffu, 0x80000000u, 0u}) {
    for (std::size_t at = 0; at + 4 <= good.size(); ++at) {
      std::vector<uint8_t> bad = good;
      Poke(bad, at, value);
      SafeDecode(&decoded, bad.data(), static_cast<int64_t>(bad.size()));  // must not crash
    }
  }
}

TEST(SafeDecode, EveryTypeSurvivesAbsurdCountsAtEveryOffset) {
  CheckType(Command());
  CheckType(State());
  CheckType(BeatState());
  CheckType(Prediction());
  CheckType(Accuracy());
  CheckType(Snapshot());
  CheckType(Heartbeat());
  CheckType(Control());
  CheckType(Ack());
}

TEST(SafeDecode, RejectsAnAbsurdCountBeforeDecodeAllocates) {
  auto bytes = Encode(Command());
  const std::size_t count_at = 8 + 8 + 8 + 8 + 24 * 8;  // fingerprint, utime, seq, t_s, arrays
  Poke(bytes, count_at, 0x7f000000u);
  odonata::wing_command_t c;
  EXPECT_FALSE(CountsFit(&c, bytes.data(), static_cast<int64_t>(bytes.size())));
  Poke(bytes, count_at, 0xffffffffu);  // −1: decode() would resize to 2^64 − 1
  EXPECT_FALSE(CountsFit(&c, bytes.data(), static_cast<int64_t>(bytes.size())));
  Poke(bytes, count_at, 4);  // one more than the message holds
  EXPECT_FALSE(SafeDecode(&c, bytes.data(), static_cast<int64_t>(bytes.size())));
}

TEST(SafeDecode, RejectsRowsOfNothingThatStillCostMemory) {
  // 2^30 rules of 0 inputs take no bytes on the wire, yet decode() would allocate 2^30 rows.
  auto m = Snapshot();
  m.models[1] = Rules(0, 0, 0, 0);
  auto bytes = Encode(m);
  odonata::model_snapshot_t d;
  ASSERT_TRUE(SafeDecode(&d, bytes.data(), static_cast<int64_t>(bytes.size())));
  // Find the second model's num_rules: after its output_name string ("roll_rad" + NUL).
  const std::vector<uint8_t> name = {0, 0, 0, 9, 'r', 'o', 'l', 'l', '_', 'r', 'a', 'd', 0};
  std::size_t last = 0;
  for (std::size_t i = 0; i + name.size() <= bytes.size(); ++i)
    if (std::equal(name.begin(), name.end(), bytes.begin() + static_cast<long>(i))) last = i;
  ASSERT_GT(last, 0u);
  Poke(bytes, last + name.size(), 1u << 30);
  EXPECT_FALSE(CountsFit(&d, bytes.data(), static_cast<int64_t>(bytes.size())));
}

TEST(SafeDecode, RejectsAZeroLengthString) {
  auto bytes = Encode(Control());
  odonata::control_t c;
  Poke(bytes, 8 + 8 + 8, 0);  // sender's length: decode() would assign 2^64 − 1 characters
  EXPECT_FALSE(SafeDecode(&c, bytes.data(), static_cast<int64_t>(bytes.size())));
}

}  // namespace
}  // namespace odonata::bus

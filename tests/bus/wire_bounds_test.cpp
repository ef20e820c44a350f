// The generated wire bounds (bus/wire_bounds.*, written from the .lcm files by
// lcmtypes/gen_wire_bounds.py) follow the .lcm files, checked against lcm-gen's own decode(),
// which lcm-gen writes from the same files. For every type: a valid message passes and each
// truncation of it fails, so the walk covers exactly the encoded bytes; and writing a negative or
// an oversized int32 over each 4-byte window of the message in turn is rejected exactly where
// decode() rejects it too, that is where the window touches a count or a string length, and
// accepted everywhere else.
#include <gtest/gtest.h>
#include <sys/resource.h>
#include <unistd.h>

#include <cstdint>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "bus/wire_bounds.hpp"
#include "odonata/fuzzy_rules_t.hpp"

#if defined(__SANITIZE_ADDRESS__)
#define ODONATA_TEST_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ODONATA_TEST_ASAN 1
#endif
#endif

namespace odonata::bus {
namespace {

template <class Msg>
std::vector<uint8_t> Encode(const Msg& m) {
  std::vector<uint8_t> buf(static_cast<std::size_t>(m.getEncodedSize()));
  EXPECT_EQ(m.encode(buf.data(), 0, static_cast<int>(buf.size())), static_cast<int>(buf.size()));
  return buf;
}

// Overwrites the 4 bytes at `at` with the big-endian `value`.
void Poke(std::vector<uint8_t>& b, std::size_t at, uint32_t value) {
  for (int i = 0; i < 4; ++i) b[at + i] = static_cast<uint8_t>(value >> (24 - 8 * i));
}

// Lowers the soft address-space limit to the process's size plus `headroom` while it lives, so
// that decode() asked for gigabytes by a corrupt count throws std::bad_alloc instead of taking the
// machine's memory. Inactive under AddressSanitizer, which reserves terabytes of address space up
// front and aborts on a failed allocation instead of throwing.
class AddressSpaceLimit {
 public:
  explicit AddressSpaceLimit(uint64_t headroom) {
#ifndef ODONATA_TEST_ASAN
    uint64_t pages = 0;
    std::ifstream("/proc/self/statm") >> pages;
    if (pages == 0 || getrlimit(RLIMIT_AS, &saved_) != 0) return;
    rlimit lowered = saved_;
    lowered.rlim_cur = pages * static_cast<uint64_t>(sysconf(_SC_PAGESIZE)) + headroom;
    if (saved_.rlim_cur != RLIM_INFINITY && lowered.rlim_cur >= saved_.rlim_cur) return;
    active_ = setrlimit(RLIMIT_AS, &lowered) == 0;
#else
    (void)headroom;
#endif
  }
  ~AddressSpaceLimit() {
    if (active_) setrlimit(RLIMIT_AS, &saved_);
  }
  AddressSpaceLimit(const AddressSpaceLimit&) = delete;
  AddressSpaceLimit& operator=(const AddressSpaceLimit&) = delete;

  bool active() const { return active_; }

 private:
  rlimit saved_{};
  bool active_ = false;
};

// lcm-gen's decode() as the oracle: true when it accepts the bytes.
template <class Msg>
bool Decodes(const std::vector<uint8_t>& bytes) {
  Msg m;
  try {
    return m.decode(bytes.data(), 0, static_cast<int>(bytes.size())) >= 0;
  } catch (...) {  // std::length_error (a negative count or length), std::bad_alloc
    return false;
  }
}

template <class Msg>
bool Fits(const std::vector<uint8_t>& bytes) {
  return CountsFit(static_cast<const Msg*>(nullptr), bytes.data(),
                   static_cast<int64_t>(bytes.size()));
}

// A valid message passes and every truncation fails. Then every 4-byte window after the
// fingerprint (CountsFit leaves that to decode()) is overwritten with −1, INT32_MAX and the
// message's size + 1, in turn: CountsFit must agree with decode(). Where CountsFit rejects,
// decode() only runs under the address-space limit, since that is where its allocations are
// unbounded; without the limit (sanitizer builds) only the accepted ones are compared.
//
// CountsFit is stricter than decode() on purpose in one way: a count larger than the message is
// rejected even when every array it sizes is empty (an inner dimension under an outer one of 0),
// so the agreement is exact only for messages whose every count sizes a non-empty array
// (`dense`); for the others, CountsFit accepting must still mean decode() accepts.
template <class Msg>
void CheckType(const Msg& msg, bool dense) {
  SCOPED_TRACE(Msg::getTypeName());
  const std::vector<uint8_t> good = Encode(msg);
  ASSERT_TRUE(Fits<Msg>(good));
  ASSERT_TRUE(Decodes<Msg>(good));
  for (std::size_t n = 0; n < good.size(); ++n) {
    const std::vector<uint8_t> cut(good.begin(), good.begin() + static_cast<long>(n));
    EXPECT_FALSE(Fits<Msg>(cut)) << "truncated to " << n << " of " << good.size();
  }

  const AddressSpaceLimit limit(uint64_t{64} << 20);
  std::ostringstream disagreements;
  int count = 0;
  const auto oversized = static_cast<uint32_t>(good.size() + 1);
  for (const uint32_t value : {0xffffffffu, 0x7fffffffu, oversized}) {
    for (std::size_t at = 8; at + 4 <= good.size(); ++at) {
      std::vector<uint8_t> bad = good;
      Poke(bad, at, value);
      const bool fits = Fits<Msg>(bad);
      if (!fits && !(limit.active() && dense)) continue;
      const bool decodes = Decodes<Msg>(bad);
      if (fits != decodes && ++count <= 10)
        disagreements << "\n  0x" << std::hex << value << std::dec << " at byte " << at
                      << ": CountsFit " << (fits ? "accepts" : "rejects") << ", decode() "
                      << (decodes ? "accepts" : "rejects");
    }
  }
  EXPECT_EQ(count, 0) << good.size() << "-byte message:" << disagreements.str();
}

odonata::wing_command_t Command(int excitations) {
  odonata::wing_command_t c{};
  c.utime = -1;
  c.seq = 12;
  c.t_s = 0.25;
  c.freq_hz[2] = 5.5;
  c.phase_rad[3] = -1.0;
  c.num_excitations = excitations;
  for (int i = 0; i < excitations; ++i) {
    c.excitation_names.push_back(i == 0 ? "" : "u_roll_rad");
    c.excitations.push_back(0.1 * i);
  }
  c.source = "preset:roll/train";
  return c;
}

odonata::plant_state_t State() {
  odonata::plant_state_t s{};
  s.seq = 5;
  s.command_seq = -1;
  s.attitude_rad[1] = 0.1;
  s.status = odonata::plant_state_t::STATUS_DIVERGED;
  return s;
}

odonata::beat_state_t BeatState() {
  odonata::beat_state_t b{};
  b.seq = 5;
  b.command_seq = 4;
  b.window_s = 0.19;
  b.applied_amp_rad[3] = 1.05;
  b.attitude_hold = 1;
  return b;
}

odonata::prediction_t Prediction(int outputs) {
  odonata::prediction_t p{};
  p.seq = 3;
  p.num_outputs = outputs;
  for (int i = 0; i < outputs; ++i) {
    p.names.push_back("out" + std::to_string(i));
    for (auto* v : {&p.measured, &p.predicted, &p.free_run, &p.next, &p.max_entropy,
                    &p.arx_predicted, &p.arx_free_run, &p.linear_share, &p.ahead, &p.arx_ahead})
      v->push_back(i + 0.5);
    p.rules.push_back(i + 1);
  }
  p.learning = 1;
  p.horizon = 50;
  p.num_ahead = outputs;
  // The intervals and "seen enough": every count of the type walked, an int8 array among them.
  p.interval_level = 0.9;
  for (int i = 0; i < outputs; ++i) {
    for (auto* v : {&p.half_width, &p.ahead_half_width, &p.free_run_half_width})
      v->push_back(0.25 * (i + 1));
    p.seen_enough.push_back(static_cast<int8_t>(i % 3));
  }
  p.num_intervals = p.num_ahead_intervals = p.num_free_run_intervals = p.num_seen_enough = outputs;
  return p;
}

odonata::accuracy_t Accuracy(int outputs) {
  odonata::accuracy_t a{};
  a.window_samples = 100;
  a.num_outputs = outputs;
  for (int i = 0; i < outputs; ++i) {
    a.names.push_back(std::string(static_cast<std::size_t>(i + 1), 'a'));
    for (auto* v :
         {&a.window_fit_one_step,     &a.window_vaf_one_step,    &a.window_rmse_one_step,
          &a.total_fit_one_step,      &a.total_vaf_one_step,     &a.total_rmse_one_step,
          &a.window_fit_free_run,     &a.window_vaf_free_run,    &a.window_rmse_free_run,
          &a.total_fit_free_run,      &a.total_vaf_free_run,     &a.total_rmse_free_run,
          &a.window_fit_one_step_arx, &a.total_fit_one_step_arx, &a.window_fit_free_run_arx,
          &a.total_fit_free_run_arx,  &a.window_fit_ahead,       &a.total_fit_ahead,
          &a.window_fit_ahead_arx,    &a.total_fit_ahead_arx})
      v->push_back(97.5 - i);
    a.rules.push_back(3 + i);
  }
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
  r.max_rules = 40;
  r.entropy_measure = "firing";
  r.rls_forgetting = 1.0;
  r.prune_min_age = 50;
  r.clock = 1000;
  r.utility_sums.assign(rules, 3.5);
  r.born.assign(rules, 7);
  return r;
}

odonata::model_snapshot_t Snapshot(std::vector<odonata::fuzzy_rules_t> models, int inputs,
                                   int regressors) {
  odonata::model_snapshot_t m{};
  m.seq = 4;
  m.learning = 1;
  m.instance = "identifier";
  m.output_lags = 2;
  m.input_lags = 1;
  m.delay = 1;
  m.num_outputs = static_cast<int32_t>(models.size());
  for (std::size_t i = 0; i < models.size(); ++i) {
    m.outputs.push_back("y" + std::to_string(i));
    m.output_mean.push_back(0.5);
    m.output_std.push_back(2.0);
    m.output_lower.push_back(-1.0);
    m.output_upper.push_back(1.0);
  }
  m.num_inputs = inputs;
  m.inputs.assign(inputs, "u_roll_rad");
  m.num_regressors = regressors;
  m.regressor_mid.assign(regressors, 1.0);
  m.regressor_half.assign(regressors, 0.5);
  m.models = std::move(models);
  return m;
}

odonata::heartbeat_t Heartbeat() {
  odonata::heartbeat_t h{};
  h.service = "odonata-identifier";
  h.instance = "a";
  h.host = "";
  h.pid = 4242;
  h.state = "running";
  h.decode_errors = 3;
  h.last_error = "decode: truncated";
  return h;
}

odonata::control_t Control() {
  odonata::control_t c{};
  c.sender = "odonata-control";
  c.target = "";
  c.command = odonata::control_t::SAVE_MODEL;
  c.value = 0.99;
  c.path = "/tmp/model.json";
  return c;
}

odonata::ack_t Ack() {
  odonata::ack_t a{};
  a.service = "odonata-logger";
  a.instance = "logger";
  a.state_seq = -1;
  return a;
}

odonata::control_reply_t Reply(int params) {
  odonata::control_reply_t r{};
  r.request_sender = "odonata-control";
  r.request_seq = 77;
  r.command = odonata::control_t::GET;
  r.service = "odonata-identifier";
  r.instance = "roll-id";
  r.accepted = true;
  r.reason = "parameters in force";
  r.num_params = params;
  for (int i = 0; i < params; ++i) {
    r.names.push_back("p" + std::to_string(i));
    r.values.push_back(0.5 * i);
  }
  return r;
}

TEST(WireBounds, FollowDecodeForEveryType) {
  CheckType(Command(2), true);
  CheckType(State(), true);
  CheckType(BeatState(), true);
  CheckType(Prediction(2), true);
  CheckType(Accuracy(2), true);
  CheckType(Snapshot({Rules(3, 2, 3, 9), Rules(1, 2, 1, 1)}, 1, 3), true);
  CheckType(Heartbeat(), true);
  CheckType(Control(), true);
  CheckType(Ack(), true);
  CheckType(Reply(3), true);
}

TEST(WireBounds, FollowDecodeWithEmptyArrays) {
  CheckType(Command(0), false);
  CheckType(Prediction(0), false);
  CheckType(Accuracy(0), false);
  CheckType(Reply(0), false);
  CheckType(Snapshot({}, 0, 0), false);
  // Rows of nothing: 2 rules of 0 inputs, and a model without rules.
  CheckType(Snapshot({Rules(2, 0, 0, 0), Rules(0, 3, 4, 16)}, 3, 7), false);
}

}  // namespace
}  // namespace odonata::bus

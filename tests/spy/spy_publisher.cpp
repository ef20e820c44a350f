// Publishes recognisable messages of odonata's types on the project's channels, for the lcm-spy
// test: every channel at RATE_HZ until SECONDS have passed. The markers (strings, seq, fixed
// values) let the test check that lcm-spy decoded the fields, not just counted the packets.
// It also publishes bytes with a fingerprint no type has on SPY_TEST_UNKNOWN, which lcm-spy must
// show as undecoded ("?? <fingerprint>"): the control that the check can tell the two apart.
// Every message of odonata's types carries a signature after its payload, as a system with a
// shared key sends them (docs/lcm.md §15): lcm-spy must decode them all the same.
//
// Usage: spy_publisher URL SECONDS RATE_HZ

#include <unistd.h>
#include <limits>

#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include <lcm/lcm-cpp.hpp>
#include <vector>

#include <odonata/accuracy_t.hpp>
#include <odonata/beat_state_t.hpp>
#include <odonata/control_t.hpp>
#include <odonata/heartbeat_t.hpp>
#include <odonata/model_snapshot_t.hpp>
#include <odonata/plant_state_t.hpp>
#include <odonata/prediction_t.hpp>
#include <odonata/wing_command_t.hpp>
#include "bus/message_signer.hpp"

namespace {

int64_t NowUs() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

// Encodes, signs with a throwaway key and publishes: what a service with --key sends.
template <class Msg>
int PublishSigned(lcm::LCM& bus, odonata::bus::MessageSigner& signer, const std::string& channel,
                  const Msg& msg) {
  std::vector<uint8_t> bytes(static_cast<std::size_t>(msg.getEncodedSize()));
  if (msg.encode(bytes.data(), 0, static_cast<int>(bytes.size())) < 0) return -1;
  signer.Sign(channel, &bytes, NowUs());
  return bus.publish(channel, bytes.data(), static_cast<unsigned>(bytes.size()));
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: %s URL SECONDS RATE_HZ\n", argv[0]);
    return 2;
  }
  const std::string url = argv[1];
  const double seconds = std::atof(argv[2]);
  const double rate_hz = std::atof(argv[3]);
  if (seconds <= 0 || rate_hz <= 0) {
    std::fprintf(stderr, "spy_publisher: SECONDS and RATE_HZ must be positive\n");
    return 2;
  }
  lcm::LCM bus(url);
  if (!bus.good()) {
    std::fprintf(stderr, "spy_publisher: cannot open LCM at %s\n", url.c_str());
    return 1;
  }

  odonata::bus::BusKey key;
  key.bytes.fill(0x42);
  odonata::bus::MessageSigner signer(key, 1);
  const auto period = std::chrono::duration<double>(1.0 / rate_hz);
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  auto next = std::chrono::steady_clock::now();
  int failures = 0;
  for (int64_t k = 1; std::chrono::steady_clock::now() < end; ++k) {
    odonata::wing_command_t cmd{};
    cmd.utime = NowUs();
    cmd.seq = k;
    cmd.t_s = 0.01 * static_cast<double>(k);
    for (int w = 0; w < 4; ++w) {
      cmd.freq_hz[w] = 30.0;
      cmd.amp_rad[w] = 1.0;
    }
    cmd.num_excitations = 1;
    cmd.excitation_names = {"u_roll"};
    cmd.excitations = {0.125};
    cmd.source = "spy-test";
    failures += PublishSigned(bus, signer, "DIMAV_COMMAND", cmd) != 0;

    odonata::plant_state_t state{};
    state.utime = NowUs();
    state.seq = k;
    state.command_seq = k - 1;
    state.t_s = cmd.t_s;
    // Gentle oscillations, so lcm-spy's sparklines have something to draw.
    const double t = state.t_s;
    state.velocity_mps[0] = 2.0 + 0.2 * std::sin(2.0 * t);
    state.rate_radps[0] = 0.3 * std::cos(3.0 * t);
    state.attitude_rad[0] = 0.1 * std::sin(3.0 * t);
    state.position_m[0] = 2.0 * t;
    state.position_m[2] = 1.5;
    state.fx_n[0] = 0.25;  // a marker the test checks
    for (int w = 1; w < 4; ++w) state.fx_n[w] = 0.25 + 0.01 * w;
    for (int w = 0; w < 4; ++w) state.fz_n[w] = 0.6 + 0.05 * std::sin(2.0 * t + w);
    state.status = odonata::plant_state_t::STATUS_OK;
    failures += PublishSigned(bus, signer, "DIMAV_STATE", state) != 0;

    odonata::beat_state_t beat{};
    beat.utime = NowUs();
    beat.seq = k;
    beat.command_seq = k - 1;
    beat.t_s = cmd.t_s;
    beat.window_s = 0.1875;
    beat.velocity_mps[0] = 2.0;
    beat.fz_total_n = 0.375;  // markers the test checks
    beat.u_roll_applied_rad = 0.125;
    beat.attitude_hold = 1;
    failures += PublishSigned(bus, signer, "DIMAV_BEAT_STATE", beat) != 0;

    odonata::heartbeat_t hb{};
    hb.utime = NowUs();
    hb.seq = k;
    hb.service = "spy-test";
    hb.instance = "spy-test-1";
    hb.host = "localhost";
    hb.pid = static_cast<int32_t>(getpid());
    hb.state = "running";
    hb.messages_out = 4 * k;
    failures += PublishSigned(bus, signer, "ODONATA_HEARTBEAT", hb) != 0;

    odonata::prediction_t pred{};
    pred.utime = NowUs();
    pred.seq = k;
    pred.sample = k;
    pred.num_outputs = 1;
    pred.names = {"roll_rad"};
    pred.measured = {0.5};
    pred.predicted = {0.5};
    pred.free_run = {0.5};
    pred.next = {0.5};
    pred.rules = {3};
    pred.max_entropy = {0.75};
    pred.arx_predicted = {0.09};
    pred.arx_free_run = {0.08};
    pred.linear_share = {0.0};
    pred.horizon = 20;
    pred.num_ahead = 1;
    pred.ahead = {0.09};
    pred.arx_ahead = {0.07};
    pred.learning = 1;
    failures += PublishSigned(bus, signer, "ODONATA_PREDICTION", pred) != 0;

    odonata::accuracy_t acc{};
    acc.utime = NowUs();
    acc.seq = k;
    acc.last_sample = k;
    acc.window_samples = 100;
    acc.total_samples = k;
    acc.num_outputs = 1;
    acc.names = {"roll_rad"};
    for (auto* v :
         {&acc.window_fit_one_step,     &acc.window_vaf_one_step,    &acc.window_rmse_one_step,
          &acc.total_fit_one_step,      &acc.total_vaf_one_step,     &acc.total_rmse_one_step,
          &acc.window_fit_free_run,     &acc.window_vaf_free_run,    &acc.window_rmse_free_run,
          &acc.total_fit_free_run,      &acc.total_vaf_free_run,     &acc.total_rmse_free_run,
          &acc.window_fit_one_step_arx, &acc.total_fit_one_step_arx, &acc.window_fit_free_run_arx,
          &acc.total_fit_free_run_arx,  &acc.window_fit_ahead,       &acc.total_fit_ahead,
          &acc.window_fit_ahead_arx,    &acc.total_fit_ahead_arx})
      *v = {95.5};
    acc.rules = {3};
    acc.horizon = 20;
    failures += PublishSigned(bus, signer, "ODONATA_ACCURACY", acc) != 0;

    odonata::control_t ctl{};
    ctl.utime = NowUs();
    ctl.seq = k;
    ctl.target = "spy-test";
    ctl.command = odonata::control_t::PUBLISH_SNAPSHOT;
    failures += PublishSigned(bus, signer, "ODONATA_CONTROL", ctl) != 0;

    odonata::model_snapshot_t snap{};
    snap.utime = NowUs();
    snap.seq = k;
    snap.samples_learned = k;
    snap.instance = "spy-test";
    snap.output_lags = snap.input_lags = snap.delay = 1;
    snap.num_outputs = 1;
    snap.outputs = {"roll_rad"};
    snap.num_inputs = 1;
    snap.inputs = {"u_roll"};
    snap.num_regressors = 2;
    snap.regressor_mid = {0.0, 0.0};
    snap.regressor_half = {1.0, 1.0};
    snap.output_mean = {0.0};
    snap.output_std = {1.0};
    snap.output_lower = {-std::numeric_limits<double>::infinity()};
    snap.output_upper = {std::numeric_limits<double>::infinity()};
    odonata::fuzzy_rules_t rules{};
    rules.output_name = "roll_rad";
    rules.num_rules = 1;
    rules.num_inputs = 2;
    rules.centres = {{0.1, 0.2}};
    rules.sigmas = {{0.3, 0.3}};
    rules.output_widths = {1.0};
    rules.utility_sums = {0.0};
    rules.born = {0};
    rules.consequent = "singleton";
    rules.num_coefficients = 1;
    rules.coefficients = {{0.5}};
    rules.entropy_measure = "rule";
    snap.models = {rules};
    failures += PublishSigned(bus, signer, "ODONATA_MODEL", snap) != 0;

    // Eight bytes of a fingerprint no generated type has, then a payload.
    const unsigned char foreign[16] = {0xde, 0xad, 0xbe, 0xef, 0x0d, 0xd0, 0x0a, 0x7a,
                                       1,    2,    3,    4,    5,    6,    7,    8};
    failures += bus.publish("SPY_TEST_UNKNOWN", foreign, sizeof foreign) != 0;

    if (failures > 0) {
      std::fprintf(stderr, "spy_publisher: publish failed (no multicast route?)\n");
      return 1;
    }
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
  return 0;
}

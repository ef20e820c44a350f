// Pipeline benchmark: latency from a state message's publish to the matching prediction's
// receipt through a running odonata-identifier, against a bare LCM round trip, and the highest
// sample rate the identifier holds without dropping a sample. Run it with
// bench/pipeline/run_pipeline_bench.sh (which starts the identifier in a private namespace).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <lcm/lcm-cpp.hpp>

#include "odonata/plant_state_t.hpp"
#include "odonata/prediction_t.hpp"
#include "odonata/wing_command_t.hpp"

namespace {

using Clock = std::chrono::steady_clock;

double Us(Clock::duration d) { return std::chrono::duration<double, std::micro>(d).count(); }

struct Percentiles {
  double p50 = 0, p99 = 0, max = 0;
};

Percentiles Summarise(std::vector<double> v) {
  if (v.empty()) return {};
  std::sort(v.begin(), v.end());
  auto at = [&v](double q) { return v[static_cast<std::size_t>(q * (v.size() - 1))]; };
  return {at(0.5), at(0.99), v.back()};
}

odonata::wing_command_t Command(int64_t k) {
  odonata::wing_command_t c{};
  c.seq = k;
  c.t_s = 0.01 * k;
  for (int w = 0; w < 4; ++w) c.freq_hz[w] = 5.4;
  c.num_excitations = 1;
  c.excitation_names = {"u"};
  c.excitations = {std::sin(0.05 * k) + 0.3 * std::sin(0.31 * k)};
  c.source = "bench";
  return c;
}

odonata::plant_state_t State(int64_t k, double y) {
  odonata::plant_state_t s{};
  s.seq = k;
  s.command_seq = k - 1;
  s.t_s = 0.01 * k;
  s.attitude_rad[0] = y;
  return s;
}

struct PredictionSink {
  int64_t last_sample = -1;
  long received = 0;
  Clock::time_point when;
  // Paced mode: when state k + 1 (which completes sample k) went out, and the latencies seen.
  std::vector<Clock::time_point>* sent = nullptr;
  std::vector<double> latency_us;
  void On(const lcm::ReceiveBuffer*, const std::string&, const odonata::prediction_t* p) {
    last_sample = p->sample;
    ++received;
    when = Clock::now();
    if (sent && p->sample >= 0 && static_cast<std::size_t>(p->sample) < sent->size())
      latency_us.push_back(Us(when - (*sent)[static_cast<std::size_t>(p->sample)]));
  }
};

struct Echo {
  lcm::LCM* lcm;
  void On(const lcm::ReceiveBuffer* rb, const std::string&) {
    lcm->publish("BENCH_PONG", rb->data, rb->data_size);
  }
};

struct Pong {
  bool got = false;
  void On(const lcm::ReceiveBuffer*, const std::string&) { got = true; }
};

}  // namespace

int main(int argc, char** argv) {
  std::string url, mode = "latency", suffix;
  long samples = 10000;
  double rate_hz = 1000;
  CLI::App app{
      "Pipeline latency and throughput through odonata-identifier (see run_pipeline_bench.sh)"};
  app.add_option("--lcm-url", url)->required();
  app.add_option("--mode", mode,
                 "echo (serve pings), rtt (bare round trip), latency (lockstep "
                 "through the identifier), rate (paced, counts drops)")
      ->check(CLI::IsMember({"echo", "rtt", "latency", "rate"}));
  app.add_option("--samples", samples)->capture_default_str();
  app.add_option("--rate-hz", rate_hz)->capture_default_str();
  app.add_option("--channel-suffix", suffix,
                 "one vehicle of a fleet: DIMAV_COMMAND_SUFFIX, DIMAV_STATE_SUFFIX and "
                 "ODONATA_PREDICTION_SUFFIX, as the identifier's --channel-suffix names them");
  CLI11_PARSE(app, argc, argv);
  const auto channel = [&suffix](const std::string& name) {
    return suffix.empty() ? name : name + "_" + suffix;
  };
  lcm::LCM lcm(url);
  if (!lcm.good()) return 1;

  if (mode == "echo") {
    Echo echo{&lcm};
    lcm.subscribe("BENCH_PING", &Echo::On, &echo);
    while (lcm.handle() == 0) {
    }
    return 0;
  }
  if (mode == "rtt") {
    Pong pong;
    lcm.subscribe("BENCH_PONG", &Pong::On, &pong);
    std::vector<double> rtt;
    const odonata::plant_state_t probe = State(1, 0.0);  // the same size as the real traffic
    for (long i = 0; i < samples; ++i) {
      pong.got = false;
      const auto t0 = Clock::now();
      lcm.publish("BENCH_PING", &probe);
      while (!pong.got && lcm.handleTimeout(100) > 0) {
      }
      if (pong.got) rtt.push_back(Us(Clock::now() - t0));
    }
    const auto p = Summarise(rtt);
    std::printf("bare LCM round trip (2 hops): p50 %.1f us, p99 %.1f us, max %.1f us over %zu\n",
                p.p50, p.p99, p.max, rtt.size());
    return 0;
  }

  PredictionSink sink;
  std::vector<Clock::time_point> sent(static_cast<std::size_t>(std::max(0L, samples)) + 1);
  sink.sent = &sent;
  lcm.subscribe(channel("ODONATA_PREDICTION"), &PredictionSink::On, &sink);
  double y = 0;
  auto step = [&](int64_t k) {
    // Sample k: state k is already out; command k, then state k+1 completes the sample.
    const auto c = Command(k);
    lcm.publish(channel("DIMAV_COMMAND"), &c);
    y = 0.8 * y + 0.2 * c.excitations[0];
    const auto s = State(k + 1, y);
    const auto t = Clock::now();
    sent[static_cast<std::size_t>(k)] = t;
    lcm.publish(channel("DIMAV_STATE"), &s);
    return t;
  };
  const auto s0 = State(0, 0.0);
  lcm.publish(channel("DIMAV_STATE"), &s0);

  if (mode == "latency") {
    std::vector<double> lat;
    long lost = 0;
    const auto start = Clock::now();
    for (int64_t k = 0; k < samples; ++k) {
      const auto t = step(k);
      const int64_t want = k;
      const auto deadline = t + std::chrono::milliseconds(100);
      while (sink.last_sample < want && Clock::now() < deadline) lcm.handleTimeout(10);
      if (sink.last_sample >= want) {
        if (k > 10) lat.push_back(Us(sink.when - t));  // skip the regressor fill
      } else if (k > 10) {
        ++lost;
      }
    }
    const double secs = std::chrono::duration<double>(Clock::now() - start).count();
    const auto p = Summarise(lat);
    std::printf(
        "state publish -> prediction receipt (2 hops + identifier): p50 %.1f us, p99 %.1f "
        "us, max %.1f us over %zu samples, %ld lost\n",
        p.p50, p.p99, p.max, lat.size(), lost);
    std::printf("lockstep (one sample in flight): %.0f samples/s\n", samples / secs);
    return lost == 0 ? 0 : 3;
  }

  // Paced: publish at rate_hz regardless of the answers, then count what came back.
  const auto period = std::chrono::duration<double>(1.0 / rate_hz);
  const auto start = Clock::now();
  for (int64_t k = 0; k < samples; ++k) {
    const auto due = start + std::chrono::duration_cast<Clock::duration>(period * k);
    // Sleep in LCM's wait while the next sample is more than 2 ms away (a fleet's producers
    // must not spin on the cores the identifiers need), spin only for the last stretch.
    for (auto now = Clock::now(); now < due; now = Clock::now()) {
      const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(due - now).count();
      lcm.handleTimeout(ms > 2 ? static_cast<int>(ms - 1) : 0);
    }
    step(k);
    lcm.handleTimeout(0);
  }
  const auto drain_until = Clock::now() + std::chrono::milliseconds(500);
  while (Clock::now() < drain_until) lcm.handleTimeout(20);
  const long expected = samples - 1;  // the first sample only fills the regressor (ny = nu = 1)
  const auto p = Summarise(sink.latency_us);
  std::printf(
      "paced %.0f Hz: %ld of %ld predictions (%ld dropped), latency p50 %.1f us, p99 %.1f us\n",
      rate_hz, sink.received, expected, std::max(0L, expected - sink.received), p.p50, p.p99);
  return sink.received >= expected ? 0 : 3;
}

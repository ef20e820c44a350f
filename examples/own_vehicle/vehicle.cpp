// A vehicle that knows nothing of odonata but one message: signals_t (lcmtypes/
// odonata_signals_t.lcm, run through lcm-gen for your language). It stands for your drone's
// flight code, or a small bridge from its own messages: each control step it publishes every
// signal it has, by name, on VEHICLE_SIGNALS, and odonata's identifier learns the ones its
// configuration names (identifier.json here).
//
// The "vehicle" is one axis of a quadrotor climbing and sinking: thrust grows with the square of
// the throttle, drag with the square of the speed, so the vertical speed answers the throttle
// nonlinearly. The throttle holds random levels (seeded) across the whole range.
//
//   own-vehicle [--rate HZ] [--samples N] [--seed S] [--lcm-url URL]

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <random>
#include <string>
#include <thread>

#include <lcm/lcm-cpp.hpp>

#include "odonata/signals_t.hpp"

namespace {

struct Options {
  double rate_hz = 100;
  long samples = 3000;
  unsigned seed = 1;
  std::string lcm_url;
};

[[noreturn]] void Usage(int code) {
  std::fprintf(code ? stderr : stdout,
               "usage: own-vehicle [--rate HZ] [--samples N] [--seed S] [--lcm-url URL]\n"
               "Publishes a simulated climbing quadrotor's signals (vz_mps, throttle, battery_v)\n"
               "as odonata signals_t on VEHICLE_SIGNALS, one message per step.\n"
               "  --rate HZ      steps per second (default 100)\n"
               "  --samples N    steps to run (default 3000)\n"
               "  --seed S       excitation seed (default 1)\n"
               "  --lcm-url URL  LCM URL (default: LCM_DEFAULT_URL)\n");
  std::exit(code);
}

Options Parse(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--help" || a == "-h") Usage(0);
    if (i + 1 >= argc) Usage(2);
    const char* v = argv[++i];
    char* end = nullptr;
    if (a == "--rate")
      o.rate_hz = std::strtod(v, &end);
    else if (a == "--samples")
      o.samples = std::strtol(v, &end, 10);
    else if (a == "--seed")
      o.seed = static_cast<unsigned>(std::strtoul(v, &end, 10));
    else if (a == "--lcm-url") {
      o.lcm_url = v;
      continue;
    } else
      Usage(2);
    if (end == v || *end != '\0') Usage(2);
  }
  if (!(o.rate_hz > 0 && o.rate_hz <= 100000) || o.samples < 1) Usage(2);
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  const Options o = Parse(argc, argv);
  lcm::LCM lcm(o.lcm_url);
  if (!lcm.good()) {
    std::fprintf(stderr, "own-vehicle: cannot open LCM (is there a multicast route?)\n");
    return 1;
  }
  std::mt19937 rng(o.seed);
  std::uniform_real_distribution<double> level(0.35, 0.95);
  std::uniform_int_distribution<int> hold(20, 80);
  const double dt = 0.01, mass = 0.5, g = 9.81, k_thrust = 9.0, k_drag = 0.08;
  double vz = 0, battery = 12.6, throttle = 0.6;
  int held = 0;
  odonata::signals_t m{};
  m.source = "own-vehicle";
  m.num_signals = 3;
  m.names = {"vz_mps", "throttle", "battery_v"};
  m.values.assign(3, 0.0);
  const auto period = std::chrono::duration<double>(1.0 / o.rate_hz);
  auto next = std::chrono::steady_clock::now();
  for (long k = 0; k < o.samples; ++k) {
    if (held-- <= 0) {
      throttle = level(rng);
      held = hold(rng);
    }
    // Sample k: the speed measured at k and the throttle applied from k on.
    m.seq = k;
    m.utime = std::chrono::duration_cast<std::chrono::microseconds>(
                  std::chrono::system_clock::now().time_since_epoch())
                  .count();
    m.values = {vz, throttle, battery};
    lcm.publish("VEHICLE_SIGNALS", &m);
    const double thrust = k_thrust * throttle * throttle;
    vz += dt * (thrust - mass * g - k_drag * vz * std::abs(vz)) / mass;
    battery -= 1e-5 * throttle;
    next += std::chrono::duration_cast<std::chrono::steady_clock::duration>(period);
    std::this_thread::sleep_until(next);
  }
  std::fprintf(stderr, "own-vehicle: %ld samples published\n", o.samples);
  return 0;
}

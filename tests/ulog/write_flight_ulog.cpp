// Writes a synthetic PX4 flight log for the programs' tests: a pitch rate driven by a control
// surface command, the rate logged at 100 Hz by one topic and the command at 50 Hz by another,
// as PX4 logs vehicle_angular_velocity and actuator_controls_0 — two rates to resample onto one.
//   write_flight_ulog OUT.ulg [SECONDS]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <random>
#include <string>

#include "ulog_writer.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: write_flight_ulog OUT.ulg [SECONDS]\n");
    return 2;
  }
  const double seconds = argc > 2 ? std::atof(argv[2]) : 60.0;
  using odonata::ulog::testing::Payload;
  odonata::ulog::testing::UlogWriter w(1, 5'000'000);
  w.FlagBits()
      .InfoText("sys_name", "PX4")
      .Format(
          "vehicle_rates:uint64_t timestamp;float roll;float pitch;float yaw;uint8_t[4] _padding0;")
      .Format("actuator_controls:uint64_t timestamp;float[8] control;")
      .ParameterFloat("MC_PITCHRATE_P", 0.15f)
      .Subscribe(0, 1, "vehicle_rates")
      .Subscribe(0, 2, "actuator_controls");
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> level(-0.6, 0.6);
  std::normal_distribution<double> noise(0.0, 0.002);
  double q = 0, u = 0;
  const int steps = static_cast<int>(seconds * 1000);  // 1 kHz integration
  for (int k = 0; k < steps; ++k) {
    const uint64_t t = 5'000'000 + static_cast<uint64_t>(k) * 1000;
    if (k % 400 == 0) u = level(rng);
    // A pitch rate with a drag that grows with it: a first-order, mildly nonlinear plant.
    q += 0.001 * (8.0 * u - 3.0 * q - 0.8 * q * std::abs(q));
    if (k % 10 == 0)
      w.Data(1,
             Payload().Put(t).Put(0.0f).Put(static_cast<float>(q + noise(rng))).Put(0.0f).Fill(4));
    if (k % 20 == 5) {
      Payload p;
      p.Put(t);
      for (int i = 0; i < 8; ++i) p.Put(static_cast<float>(i == 1 ? u : 0.0));
      w.Data(2, p);
    }
  }
  std::ofstream out(argv[1], std::ios::binary);
  out << w.bytes();
  return out ? 0 : 1;
}

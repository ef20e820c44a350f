// Writes a synthetic flight log as current PX4 firmware logs it, for the programs' tests: the
// topics a pitch-rate identification reads, each at its own realistic rate —
//   vehicle_angular_velocity  xyz[3]          400 Hz  (rad/s)
//   vehicle_torque_setpoint   xyz[3]          100 Hz  (the rate controller's torque command)
//   vehicle_thrust_setpoint   xyz[3]          100 Hz
//   actuator_motors           control[12]      50 Hz
//   vehicle_attitude          q[4]            100 Hz
//   vehicle_land_detected     landed (bool)     1 Hz, and when it changes
// On the ground for the first and last two seconds (no torque, no thrust), airborne between,
// where the pitch rate answers the torque command as a first-order, mildly nonlinear plant.
//   write_px4_flight_ulog OUT.ulg [SECONDS] [--ground]   (--ground: never leaves the ground)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <random>
#include <string>

#include "ulog_writer.hpp"

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: write_px4_flight_ulog OUT.ulg [SECONDS] [--ground]\n");
    return 2;
  }
  const double seconds = argc > 2 ? std::atof(argv[2]) : 60.0;
  const bool ground = argc > 3 && std::strcmp(argv[3], "--ground") == 0;
  using odonata::ulog::testing::Payload;
  odonata::ulog::testing::UlogWriter w(1, 2'000'000);
  w.FlagBits()
      .InfoText("sys_name", "PX4")
      .InfoText("ver_sw_release", "v1.14.0")
      .Format(
          "vehicle_angular_velocity:uint64_t timestamp;uint64_t timestamp_sample;float[3] xyz;"
          "float[3] xyz_derivative;")
      .Format("vehicle_torque_setpoint:uint64_t timestamp;uint64_t timestamp_sample;float[3] xyz;")
      .Format("vehicle_thrust_setpoint:uint64_t timestamp;uint64_t timestamp_sample;float[3] xyz;")
      .Format(
          "actuator_motors:uint64_t timestamp;uint64_t timestamp_sample;uint16_t reversible_flags;"
          "float[12] control;")
      .Format("vehicle_attitude:uint64_t timestamp;uint64_t timestamp_sample;float[4] q;")
      .Format("vehicle_land_detected:uint64_t timestamp;bool landed;bool maybe_landed;")
      .Subscribe(0, 1, "vehicle_angular_velocity")
      .Subscribe(0, 2, "vehicle_torque_setpoint")
      .Subscribe(0, 3, "vehicle_thrust_setpoint")
      .Subscribe(0, 4, "actuator_motors")
      .Subscribe(0, 5, "vehicle_attitude")
      .Subscribe(0, 6, "vehicle_land_detected");
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> level(-0.08, 0.08);
  std::normal_distribution<double> noise(0.0, 0.003);
  double q = 0, theta = 0, tau = 0;
  bool was_landed = true;
  const int steps = static_cast<int>(seconds * 2000);  // 2 kHz integration
  for (int k = 0; k < steps; ++k) {
    const double t_s = k / 2000.0;
    const uint64_t t = 2'000'000 + static_cast<uint64_t>(k) * 500;
    const bool landed = ground || t_s < 2.0 || t_s > seconds - 2.0;
    const double thrust = landed ? 0.0 : -0.55;
    if (k % 300 == 0) tau = landed ? 0.0 : level(rng);
    q += 0.0005 * (30.0 * tau - 5.0 * q - 2.0 * q * std::abs(q));
    theta += 0.0005 * q;
    if (k % 5 == 0) {  // 400 Hz
      Payload p;
      p.Put(t)
          .Put(t)
          .Put(static_cast<float>(noise(rng)))
          .Put(static_cast<float>(q + noise(rng)))
          .Put(0.0f)
          .Put(0.0f)
          .Put(0.0f)
          .Put(0.0f);
      w.Data(1, p);
    }
    if (k % 20 == 3) {  // 100 Hz
      w.Data(2, Payload().Put(t).Put(t).Put(0.0f).Put(static_cast<float>(tau)).Put(0.0f));
      w.Data(3, Payload().Put(t).Put(t).Put(0.0f).Put(0.0f).Put(static_cast<float>(thrust)));
      const double h = 0.5 * theta;
      w.Data(5, Payload()
                    .Put(t)
                    .Put(t)
                    .Put(static_cast<float>(std::cos(h)))
                    .Put(0.0f)
                    .Put(static_cast<float>(std::sin(h)))
                    .Put(0.0f));
    }
    if (k % 40 == 7) {  // 50 Hz
      Payload p;
      p.Put(t).Put(t).Put(std::uint16_t{0});
      const double base = -thrust;
      const double mix[4] = {base + tau, base - tau, base + tau, base - tau};
      for (int i = 0; i < 12; ++i) p.Put(static_cast<float>(i < 4 ? mix[i] : 0.0));
      w.Data(4, p);
    }
    if (k % 2000 == 11 || landed != was_landed) {  // 1 Hz, and on change
      w.Data(6, Payload().Put(t).Put(static_cast<std::uint8_t>(landed)).Put(std::uint8_t{0}));
      was_landed = landed;
    }
  }
  std::ofstream out(argv[1], std::ios::binary);
  out << w.bytes();
  return out ? 0 : 1;
}

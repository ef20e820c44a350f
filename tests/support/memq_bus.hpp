#pragma once
// In-process service tests over memq://: memq delivers within one LCM instance, so a test talks
// to a node through the node's own BusNode and turns the node's Asio loop itself.

#include <chrono>
#include <string>

#include "bus/bus_node.hpp"

namespace odonata::testing {

/// A BusNode's options for `service` over memq://, without heartbeat traffic to wade through.
inline bus::BusOptions MemqOptions(const std::string& service) {
  bus::BusOptions o;
  o.lcm_url = "memq://";
  o.service = service;
  o.heartbeat_period_s = 0;
  return o;
}

/// Runs the loop for `ms`, then on until nothing is ready: delivers what is queued (also what the
/// handlers publish meanwhile, one message per turn of the loop) and fires due timers, however
/// long a handler took on a busy machine.
inline void Pump(bus::BusNode& bus, int ms) {
  bus.io().restart();
  bus.io().run_for(std::chrono::milliseconds(ms));
  for (int i = 0; i < 100000 && bus.io().poll() > 0; ++i) bus.io().restart();
}

}  // namespace odonata::testing

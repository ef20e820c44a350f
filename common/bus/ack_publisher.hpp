#pragma once
// The receipts a lockstep consumer sends as ack_t on ODONATA_ACK, alike for every consumer: after
// every state, a resend's too, so a lost receipt is repaired by the generator's resend; otherwise
// only when the held state moved. The protocol: docs/lcm.md §10.

#include <cstdint>
#include <string>

#include "bus/bus_node.hpp"

namespace odonata::bus {

class AckPublisher {
 public:
  AckPublisher(BusNode& bus, std::string channel) : bus_(bus), channel_(std::move(channel)) {}

  /// `held`: the newest state held with all it needs (negative: none yet, nothing is sent).
  /// `after_state`: called for a state message (always answered).
  void Publish(int64_t held, bool after_state);

 private:
  BusNode& bus_;
  std::string channel_;
  int64_t seq_ = 0;
  int64_t last_ = -1;
};

}  // namespace odonata::bus

#pragma once
// The receipts a lockstep consumer sends as ack_t on ODONATA_ACK, alike for every consumer: one
// when the held state moves, and one for every repeated state (the generator's resend), so a
// lost receipt is repaired by the resend. The protocol is in docs/lcm.md §10.

#include <cstdint>
#include <string>

#include "bus/bus_node.hpp"

namespace odonata::bus {

class AckPublisher {
 public:
  AckPublisher(BusNode& bus, std::string channel) : bus_(bus), channel_(std::move(channel)) {}

  /// `held`: the newest state held with all it needs (negative: none yet, nothing is sent).
  /// `state_seq`: the seq of the state message just handled, or negative after any other
  /// message. A state seen before is a resend: it is answered even when `held` has not moved.
  void Publish(int64_t held, int64_t state_seq = -1);

  int64_t sent() const { return seq_; }

 private:
  BusNode& bus_;
  std::string channel_;
  int64_t seq_ = 0;
  int64_t last_ = -1;
  int64_t newest_state_ = -1;
};

}  // namespace odonata::bus

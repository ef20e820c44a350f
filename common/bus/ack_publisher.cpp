#include "bus/ack_publisher.hpp"

#include "odonata/ack_t.hpp"

namespace odonata::bus {

void AckPublisher::Publish(int64_t held, bool after_state) {
  if (held < 0 || (!after_state && held == last_)) return;
  last_ = held;
  odonata::ack_t a{};
  a.utime = NowUtime();
  a.seq = seq_++;
  a.service = bus_.options().service;
  a.instance = bus_.options().instance;
  a.state_seq = held;
  bus_.Publish(channel_, a);
}

}  // namespace odonata::bus

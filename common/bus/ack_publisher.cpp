#include "bus/ack_publisher.hpp"

#include <algorithm>

#include "odonata/ack_t.hpp"

namespace odonata::bus {

void AckPublisher::Publish(int64_t held, int64_t state_seq) {
  // A state's first copy usually arrives before its beat state, so answering it would repeat
  // the previous receipt: one datagram per sample more for every process on the bus to wake for.
  const bool resent = state_seq >= 0 && state_seq <= newest_state_;
  newest_state_ = std::max(newest_state_, state_seq);
  if (held < 0 || (held == last_ && !resent)) return;
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

// AckPublisher: one receipt per sample (when the held state moves), and one more for every state
// seen again, since a repeated state is the generator's resend asking for a lost receipt.
#include <gtest/gtest.h>

#include <vector>

#include "bus/ack_publisher.hpp"
#include "odonata/ack_t.hpp"
#include "support/memq_bus.hpp"

namespace odonata::bus {
namespace {

TEST(AckPublisher, ReceiptsWhenHeldMovesAndForEveryResentState) {
  BusNode bus(testing::MemqOptions("odonata-identifier"));
  std::vector<int64_t> receipts;
  bus.Subscribe<odonata::ack_t>("ACK",
                                [&](const odonata::ack_t& a) { receipts.push_back(a.state_seq); });
  AckPublisher acks(bus, "ACK");
  acks.Publish(-1, 0);  // state 0 arrives, nothing held yet: no receipt
  acks.Publish(0);      // its beat state: state 0 held
  acks.Publish(0, 1);   // state 1, beat not yet in: held has not moved, no receipt
  acks.Publish(1);      // beat 1: receipt for 1
  acks.Publish(1);      // a command: nothing moved
  acks.Publish(1, 1);   // state 1 again (a resend): answered although nothing moved
  acks.Publish(2, 2);   // a configuration without beat states: the state alone moves held
  testing::Pump(bus, 5);
  EXPECT_EQ(receipts, (std::vector<int64_t>{0, 1, 1, 2}));
  EXPECT_EQ(acks.sent(), 4);
}

}  // namespace
}  // namespace odonata::bus

// The receipts a lockstep replay waits for: a sample is confirmed once every awaited consumer
// holds it; strangers and leftovers from an earlier run change nothing.
#include "replay/lockstep_receipts.hpp"

#include <gtest/gtest.h>

namespace odonata::replay {
namespace {

TEST(LockstepReceipts, ConfirmedOnceEveryAwaitedConsumerHoldsTheSample) {
  LockstepReceipts r({"id"});
  r.Await("logger");
  r.Await("id");  // once
  EXPECT_EQ(r.consumers(), (std::vector<std::string>{"id", "logger"}));
  EXPECT_FALSE(r.Confirmed(0));
  r.OnReceipt("id", 0, 0);
  EXPECT_FALSE(r.Confirmed(0));
  EXPECT_EQ(r.Missing(0), (std::vector<std::string>{"logger"}));
  r.OnReceipt("stranger", 0, 0);
  EXPECT_FALSE(r.Confirmed(0));
  r.OnReceipt("logger", 0, 0);
  EXPECT_TRUE(r.Confirmed(0));
  EXPECT_FALSE(r.Confirmed(1));
}

TEST(LockstepReceipts, AReceiptBeyondWhatWasSentOrLateAndOlderChangesNothing) {
  LockstepReceipts r({"id"});
  r.OnReceipt("id", 5000, 3);  // an earlier run's
  EXPECT_FALSE(r.Confirmed(3));
  r.OnReceipt("id", 3, 3);
  r.OnReceipt("id", 2, 3);  // out of order
  EXPECT_TRUE(r.Confirmed(3));
  r.Restart();
  EXPECT_FALSE(r.Confirmed(0));
  EXPECT_TRUE(LockstepReceipts().Confirmed(7)) << "nobody to wait for";
}

}  // namespace
}  // namespace odonata::replay

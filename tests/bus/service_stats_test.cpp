// A service under a flood of bad input prints each kind of problem once (a log line per packet
// would drown the terminal and the disk) while last_error always names the newest.
#include "bus/service_stats.hpp"

#include <gtest/gtest.h>

namespace odonata::bus {
namespace {

int Count(const std::string& text, const std::string& what) {
  int n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(ServiceStats, EachKindIsPrintedOnceAndTheLastErrorIsKept) {
  ServiceStats s;
  ::testing::internal::CaptureStderr();
  for (int i = 0; i < 100; ++i)
    s.Report("plant", "undecodable message", "packet " + std::to_string(i));
  s.Report("plant", "gap in states", "missing 3");
  s.Report("plant", "undecodable message", "packet 100");
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(Count(err, "undecodable message"), 1) << err;
  EXPECT_EQ(Count(err, "gap in states"), 1) << err;
  EXPECT_NE(err.find("[plant] undecodable message: packet 0"), std::string::npos) << err;
  EXPECT_EQ(s.last_error, "undecodable message: packet 100");
}

// A second, different problem of the same kind (on the same channel) is printed too.
TEST(ServiceStats, ADifferentProblemOfTheSameKindIsPrinted) {
  ServiceStats s;
  ::testing::internal::CaptureStderr();
  s.Report("id", "rejected message on DIMAV_STATE", "duplicate or out-of-order state seq 4");
  s.Report("id", "rejected message on DIMAV_STATE", "duplicate or out-of-order state seq 9");
  s.Report("id", "rejected message on DIMAV_STATE", "state with NaN or Inf fields");
  for (int i = 0; i < 1000; ++i)
    s.Report("id", "rejected message on DIMAV_STATE",
             "unknown thing '" + std::string(1 + i % 500, 'x') + "'");
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(Count(err, "out-of-order"), 1) << err;
  EXPECT_EQ(Count(err, "NaN or Inf"), 1) << err;
  EXPECT_LE(Count(err, "\n"), 256);  // bounded whatever the flood
}

}  // namespace
}  // namespace odonata::bus

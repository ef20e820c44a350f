// The logger's disk budget and per-message size limit (issue 24 point 5): a flood of forged
// traffic cannot fill the disk; what is refused is counted as dropped and said on the heartbeat.
#include "logger_node.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "odonata/heartbeat_t.hpp"
#include "support/memq_bus.hpp"

namespace odonata::logger {
namespace {

TEST(LoggerNode, RefusesOversizeMessagesAndStopsAtItsDiskBudget) {
  char tmpl[] = "/tmp/odonata_logger_test_XXXXXX";
  ASSERT_NE(mkdtemp(tmpl), nullptr);
  const std::string dir = tmpl;
  bus::BusNode bus(testing::MemqOptions("odonata-logger"));
  std::vector<std::string> states;
  bus.Subscribe<odonata::heartbeat_t>(bus.channels().heartbeat,
                                      [&](const auto& h) { states.push_back(h.state); });
  RecordOptions o;
  o.channels_regex = "FLOOD.*";
  o.prefix = dir + "/log";
  o.max_event_bytes = 1000;
  o.max_bytes = 10000;
  LoggerNode node(bus, o);
  const std::vector<char> small(500, 'a'), large(5000, 'b');
  bus.lcm().publish("FLOOD", large.data(), static_cast<unsigned>(large.size()));
  testing::Pump(bus, 2);
  EXPECT_EQ(node.writer().events(), 0);
  EXPECT_EQ(bus.stats().dropped, 1);
  for (int i = 0; i < 40; ++i) {
    bus.lcm().publish("FLOOD", small.data(), static_cast<unsigned>(small.size()));
    testing::Pump(bus, 1);
  }
  // 500 bytes + 33 of header and channel name each: 18 fit in 10 000 bytes, 22 are refused.
  EXPECT_EQ(node.writer().events(), 18);
  EXPECT_LE(node.writer().bytes(), 10000);
  EXPECT_EQ(bus.stats().dropped, 1 + 22);
  ASSERT_FALSE(states.empty());
  EXPECT_EQ(states.back(), "disk budget spent: not recording");
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace odonata::logger

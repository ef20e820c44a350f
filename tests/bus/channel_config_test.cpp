// Channel names: a suffix for a second system on the bus, and any single name overridden.
#include "bus/channel_config.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

namespace odonata::bus {
namespace {

TEST(ChannelConfig, SuffixThenExplicitNames) {
  ChannelConfig c;
  c.Configure("B", {"state=VEHICLE7_STATE", "control=OPS"});
  EXPECT_EQ(c.state, "VEHICLE7_STATE");  // taken as given, no suffix
  EXPECT_EQ(c.control, "OPS");
  EXPECT_EQ(c.command, "DIMAV_COMMAND_B");
  EXPECT_EQ(c.heartbeat, "ODONATA_HEARTBEAT_B");
  c.Set("model=M=odd");  // only the first '=' separates
  EXPECT_EQ(c.model, "M=odd");
}

TEST(ChannelConfig, BeatStateChannelIsNamedLikeTheOthers) {
  ChannelConfig c;
  EXPECT_EQ(c.beat_state, "DIMAV_BEAT_STATE");
  c.Configure("B", {});
  EXPECT_EQ(c.beat_state, "DIMAV_BEAT_STATE_B");
  c.Set("beat_state=VEHICLE7_BEAT");
  EXPECT_EQ(c.beat_state, "VEHICLE7_BEAT");
}

TEST(ChannelConfig, MalformedOrUnknownAssignmentsAreClearErrors) {
  ChannelConfig c;
  for (const char* bad : {"state", "=X", "state=", "stat=X"}) {
    try {
      c.Set(bad);
      ADD_FAILURE() << bad << " was accepted";
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(std::string(bad).substr(0, 4)), std::string::npos)
          << e.what();
    }
  }
  EXPECT_EQ(c.state, "DIMAV_STATE");
}

}  // namespace
}  // namespace odonata::bus

// The damage scenario's wing: what is commanded and what is flown.

#include <gtest/gtest.h>

#include "plant/actuator_damage.hpp"

namespace odonata::plant {
namespace {

TEST(ActuatorDamage, ScalesOneWingFromItsTimeOn) {
  ActuatorDamage d;
  d.at_s = 2.0;
  d.wing = 3;
  d.amplitude_scale = 0.7;
  d.frequency_scale = 0.9;
  EXPECT_TRUE(d.Problems().empty());
  CommandMatrix c = CommandMatrix::Constant(1.0);
  EXPECT_EQ(d.Apply(c, 1.99), c);
  const CommandMatrix after = d.Apply(c, 2.0);
  for (int w = 0; w < kWingCount; ++w) {
    for (int i = 0; i < kCommandsPerWing; ++i) {
      double expected = 1.0;
      if (w == 2 && i == kStrokeAmplitude) expected = 0.7;
      if (w == 2 && i == kFlapFrequency) expected = 0.9;
      EXPECT_DOUBLE_EQ(after(w, i), expected) << w << "," << i;
    }
  }
  EXPECT_EQ(ActuatorDamage{}.Apply(c, 1e9), c) << "no damage by default";
}

TEST(ActuatorDamage, NamesEveryProblem) {
  ActuatorDamage d;
  d.wing = 5;
  d.amplitude_scale = 1.2;
  d.frequency_scale = 0.0;
  d.at_s = -1;
  const std::string p = d.Problems();
  EXPECT_NE(p.find("wing"), std::string::npos);
  EXPECT_NE(p.find("amplitude"), std::string::npos);
  EXPECT_NE(p.find("frequency"), std::string::npos);
  EXPECT_NE(p.find("time"), std::string::npos);
}

}  // namespace
}  // namespace odonata::plant

namespace odonata::plant {
namespace {

// Wing 0 is a sagging battery: every wing flies the scaled frequency.
TEST(ActuatorDamage, WingZeroDamagesEveryWing) {
  CommandMatrix c = CommandMatrix::Zero();
  c.col(kFlapFrequency).setConstant(6.0);
  c.col(kStrokeAmplitude).setConstant(1.0);
  ActuatorDamage d;
  d.at_s = 1.0;
  d.wing = 0;
  d.frequency_scale = 0.9;
  EXPECT_EQ(d.Problems(), "");
  EXPECT_EQ(d.Apply(c, 0.5), c);
  const CommandMatrix after = d.Apply(c, 1.0);
  for (int w = 0; w < kWingCount; ++w) {
    EXPECT_DOUBLE_EQ(after(w, kFlapFrequency), 5.4);
    EXPECT_DOUBLE_EQ(after(w, kStrokeAmplitude), 1.0);
  }
  d.wing = -1;
  EXPECT_NE(d.Problems(), "");
}

}  // namespace
}  // namespace odonata::plant

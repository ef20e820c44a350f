// Conditions that keep part of a log: parsed as written, NaN never meeting one.
#include "timeseries/keep_condition.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

namespace odonata::timeseries {
namespace {

TEST(KeepCondition, ParsesEveryOperatorAndKeepsTheSignalName) {
  const KeepCondition c = ParseKeepCondition("vehicle_thrust_setpoint.xyz[2] <= -0.1");
  EXPECT_EQ(c.signal, "vehicle_thrust_setpoint.xyz[2]");
  EXPECT_EQ(c.op, KeepCondition::Op::kLessEqual);
  EXPECT_DOUBLE_EQ(c.value, -0.1);
  EXPECT_TRUE(c.Holds(-0.2));
  EXPECT_FALSE(c.Holds(0.0));
  EXPECT_FALSE(c.Holds(std::nan("")));
  EXPECT_EQ(ParseKeepCondition("a>1").op, KeepCondition::Op::kGreater);
  EXPECT_EQ(ParseKeepCondition("a>=1").op, KeepCondition::Op::kGreaterEqual);
  EXPECT_EQ(ParseKeepCondition("a<1").op, KeepCondition::Op::kLess);
  EXPECT_EQ(ParseKeepCondition("a!=1").op, KeepCondition::Op::kNotEqual);
  EXPECT_EQ(ParseKeepCondition("landed==0").ToString(), "landed==0");
  EXPECT_EQ(Px4Airborne().ToString(), "vehicle_land_detected.landed==0");
  EXPECT_TRUE(Px4Airborne().Holds(0.0));
  EXPECT_FALSE(Px4Airborne().Holds(1.0));
}

TEST(KeepCondition, SaysWhatAConditionLooksLike) {
  for (const char* bad : {"", "landed", "==0", "landed==", "landed==zero", "landed==nan"}) {
    try {
      ParseKeepCondition(bad);
      ADD_FAILURE() << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find("SIGNAL OP VALUE"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace odonata::timeseries

// The signals of DataFlash logs: names as ArduPilot users write them (instances included), values
// scaled by the format character or FMTU's multiplier, units from FMTU and UNIT, times in seconds
// from TimeUS or TimeMS, states held, and names that are no signal answered with the nearest.
#include <gtest/gtest.h>

#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"
#include "dataflash_writer.hpp"

namespace odonata::dataflash {
namespace {

using testing::DataflashWriter;
using timeseries::Interpolation;

DataflashFile ParseLog(const DataflashWriter& w) { return Parse(w.bytes(), "log.bin"); }

std::map<std::string, SignalInfo> SignalsByName(const DataflashFile& f) {
  std::map<std::string, SignalInfo> out;
  for (const SignalInfo& s : ListSignals(f)) out.emplace(s.name, s);
  return out;
}

std::vector<std::string> SignalNames(const DataflashFile& f) {
  std::vector<std::string> out;
  for (const SignalInfo& s : ListSignals(f)) out.push_back(s.name);
  return out;
}

// What Extract says about `name`; "" when it is a signal.
std::string ExtractError(const DataflashFile& f, const std::string& name) {
  try {
    (void)Extract(f, name);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

void ExpectValues(const timeseries::TimedSignal& s, const std::vector<double>& t_s,
                  const std::vector<double>& values) {
  ASSERT_EQ(s.t_s.size(), t_s.size()) << s.name;
  ASSERT_EQ(s.values.size(), values.size()) << s.name;
  for (std::size_t i = 0; i < t_s.size(); ++i) {
    EXPECT_EQ(s.t_s[i], t_s[i]) << s.name << " sample " << i;  // µs / 1e6: rounded once
    EXPECT_DOUBLE_EQ(s.values[i], values[i]) << s.name << " sample " << i;
  }
}

TEST(DataflashSignals, NamedAsArduPilotUsersWriteThem) {
  const DataflashFile f = ParseLog(testing::FlightLog());
  // MSG holds text only, FMT no time: neither has signals.
  EXPECT_EQ(SignalNames(f), (std::vector<std::string>{"ATT.Roll", "ATT.Pitch", "ATT.Yaw",
                                                      "MODE.Mode", "MODE.ModeNum"}));
  const auto signals = SignalsByName(f);
  const SignalInfo& roll = signals.at("ATT.Roll");
  EXPECT_EQ(roll.message, "ATT");
  EXPECT_EQ(roll.instance, -1);
  EXPECT_EQ(roll.unit, "");
  EXPECT_DOUBLE_EQ(roll.multiplier, 0.01);
  EXPECT_EQ(roll.samples, 3u);
  EXPECT_EQ(roll.out_of_order, 0u);
  EXPECT_NEAR(roll.median_rate_hz, 10.0, 1e-9);
  EXPECT_EQ(roll.interpolation, Interpolation::kLinear);
  EXPECT_EQ(signals.at("MODE.Mode").interpolation, Interpolation::kHold);
  EXPECT_EQ(signals.at("MODE.ModeNum").interpolation, Interpolation::kHold);
  EXPECT_NEAR(signals.at("MODE.Mode").median_rate_hz, 5.0, 1e-9);

  // c and C are centi-units, as pymavlink reads them.
  const timeseries::TimedSignal pitch = Extract(f, "ATT.Pitch");
  EXPECT_EQ(pitch.name, "ATT.Pitch");
  EXPECT_EQ(pitch.interpolation, Interpolation::kLinear);
  ExpectValues(pitch, {1.0, 1.1, 1.2}, {-2.5, -2.4, -2.3});
  ExpectValues(Extract(f, "ATT.Yaw"), {1.0, 1.1, 1.2}, {359.99, 0.01, 0.02});
  ExpectValues(Extract(f, "MODE.Mode"), {1.05, 1.25}, {5, 10});
}

TEST(DataflashSignals, UnitsAndMultipliersComeFromFmtu) {
  const DataflashFile f = ParseLog(testing::UnitsLog());
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.unit_labels.at('d'), "deg");
  EXPECT_DOUBLE_EQ(f.multipliers.at('C'), 0.001);
  EXPECT_EQ(f.units.at(132).unit_ids, "sdGYo");
  EXPECT_EQ(f.units.at(132).mult_ids, "F0C-?");
  const MessageFormat& sens = *f.FindFormat("SENS");
  EXPECT_EQ(f.UnitOf(sens, 0), "s");
  EXPECT_EQ(f.MultiplierOf(sens, 0), 1e-6);
  EXPECT_FALSE(f.MultiplierOf(sens, 3).has_value());  // '-'
  EXPECT_EQ(f.MultiplierOf(sens, 4), 1.0);            // '?'
  EXPECT_FALSE(f.InstanceField(sens).has_value());

  const auto signals = SignalsByName(f);
  // A scaled format character wins over FMTU's multiplier ('0' here)...
  EXPECT_EQ(signals.at("SENS.Ang").unit, "deg");
  EXPECT_DOUBLE_EQ(signals.at("SENS.Ang").multiplier, 0.01);
  ExpectValues(Extract(f, "SENS.Ang"), {2.0, 2.1}, {45.0, -45.0});
  // ...and an unscaled one takes it: milligauss × 0.001 is in gauss.
  EXPECT_EQ(signals.at("SENS.Fld").unit, "Gauss");
  EXPECT_DOUBLE_EQ(signals.at("SENS.Fld").multiplier, 0.001);
  ExpectValues(Extract(f, "SENS.Fld"), {2.0, 2.1}, {0.25, -0.25});
  EXPECT_EQ(signals.at("SENS.Pwm").unit, "us");
  EXPECT_EQ(signals.at("SENS.Pwm").multiplier, 1.0);
  ExpectValues(Extract(f, "SENS.Pwm"), {2.0, 2.1}, {1500, 1100});
  EXPECT_EQ(signals.at("SENS.Acc").unit, "m/s/s");
  ExpectValues(Extract(f, "SENS.Acc"), {2.0, 2.1}, {9.75, -9.75});
  // The unit tables' own records are messages like any other.
  EXPECT_EQ(signals.count("MULT.Mult"), 1u);
  EXPECT_EQ(signals.count("UNIT.Label"), 0u);  // text
}

TEST(DataflashSignals, InstancesNameTheirSignals) {
  const DataflashFile f = ParseLog(testing::InstancesLog());
  ASSERT_TRUE(f.complete()) << f.problem;
  EXPECT_EQ(f.InstanceField(*f.FindFormat("IMU")), 1u);
  EXPECT_EQ(SignalNames(f), (std::vector<std::string>{"FMTU.FmtType", "IMU.GyrX", "IMU.GyrY",
                                                      "IMU[1].GyrX", "IMU[1].GyrY"}));
  const auto signals = SignalsByName(f);
  EXPECT_EQ(signals.at("IMU.GyrX").instance, 0);
  EXPECT_EQ(signals.at("IMU.GyrX").samples, 3u);
  EXPECT_EQ(signals.at("IMU[1].GyrX").instance, 1);
  EXPECT_EQ(signals.at("IMU[1].GyrX").samples, 2u);
  EXPECT_NEAR(signals.at("IMU[1].GyrX").median_rate_hz, 1000.0, 1e-6);
  ExpectValues(Extract(f, "IMU.GyrX"), {0.001, 0.002, 0.003}, {0.5, 0.25, 0.125});
  // Instance 0 also answers to its index.
  const timeseries::TimedSignal zero = Extract(f, "IMU[0].GyrX");
  EXPECT_EQ(zero.name, "IMU[0].GyrX");
  ExpectValues(zero, {0.001, 0.002, 0.003}, {0.5, 0.25, 0.125});
  ExpectValues(Extract(f, "IMU[1].GyrX"), {0.001, 0.002}, {1.5, 1.25});
  ExpectValues(Extract(f, "IMU[1].GyrY"), {0.001, 0.002}, {-1.5, -1.25});
  EXPECT_TRUE(ExtractError(f, "IMU.I").find("instance number") != std::string::npos)
      << ExtractError(f, "IMU.I");
  EXPECT_TRUE(ExtractError(f, "IMU[2].GyrX").find("no records of that instance") !=
              std::string::npos)
      << ExtractError(f, "IMU[2].GyrX");
}

TEST(DataflashSignals, TimeMsTimeGoingBackTextAndArrays) {
  const DataflashFile f = ParseLog(testing::OddFieldsLog());
  ASSERT_TRUE(f.complete()) << f.problem;
  const auto signals = SignalsByName(f);
  // TimeMS; the record at 1.4 s, after one at 1.5 s, is dropped and counted.
  EXPECT_EQ(signals.at("GMB.Tq").out_of_order, 1u);
  EXPECT_EQ(signals.at("GMB.Tq").samples, 2u);
  ExpectValues(Extract(f, "GMB.Tq"), {1.5, 1.6}, {-300, 20});
  const timeseries::TimedSignal state = Extract(f, "GMB.St");
  EXPECT_EQ(state.interpolation, Interpolation::kHold);
  ExpectValues(state, {1.5, 1.6}, {-2, 3});
  // No time, no signals; a label given twice names its first field.
  EXPECT_EQ(signals.count("EV.Id"), 0u);
  EXPECT_TRUE(ExtractError(f, "EV.Id").find("no TimeUS or TimeMS") != std::string::npos)
      << ExtractError(f, "EV.Id");
  ExpectValues(Extract(f, "BAT.Volt"), {5.0}, {12.5});
  // An int16_t[32] field: one signal per element.
  EXPECT_EQ(signals.count("ISB.x[0]") + signals.count("ISB.x[31]"), 2u);
  EXPECT_EQ(signals.count("ISB.x[32]"), 0u);
  ExpectValues(Extract(f, "ISB.x[0]"), {5.0}, {100});
  ExpectValues(Extract(f, "ISB.x[31]"), {5.0}, {131});
  EXPECT_TRUE(ExtractError(f, "ISB.x[32]").find("has elements x[0] to x[31]") != std::string::npos)
      << ExtractError(f, "ISB.x[32]");
  // Latitude and longitude in 1e-7 degrees, an e field in centi-units.
  ExpectValues(Extract(f, "POS.Lat"), {5.0}, {-35.363261});
  ExpectValues(Extract(f, "POS.Lng"), {5.0}, {149.1652374});
  ExpectValues(Extract(f, "POS.Alt"), {5.0}, {584.2});
}

TEST(DataflashSignals, ANameThatIsNoSignalIsAnsweredWithTheNearest) {
  const DataflashFile f = ParseLog(testing::FlightLog());
  const std::string typo = ExtractError(f, "ATT.Pich");
  EXPECT_TRUE(typo.find("no signal 'ATT.Pich' in log.bin") != std::string::npos) << typo;
  EXPECT_TRUE(typo.find("nearest: ATT.Pitch, ") != std::string::npos) << typo;
  EXPECT_TRUE(ExtractError(f, "MSG.Message").find("is text") != std::string::npos);
  EXPECT_TRUE(ExtractError(f, "ATT").find("MESSAGE.FIELD") != std::string::npos);
  EXPECT_TRUE(ExtractError(f, "ATT.TimeUS").find("is the time") != std::string::npos);
  EXPECT_THROW(Extract(f, ""), std::invalid_argument);

  DataflashWriter w = testing::FlightLog();
  w.Fmt(141, "BAD", "Qx", "TimeUS,X", 14);
  w.Raw(std::string{'\xA3', '\x95', '\x8d'} + std::string(11, '\x02'));
  w.Fmt(143, "NONE", "Qf", "TimeUS,X");
  const DataflashFile odd = ParseLog(w);
  EXPECT_TRUE(ExtractError(odd, "BAD.X").find("cannot be decoded") != std::string::npos);
  EXPECT_TRUE(ExtractError(odd, "NONE.X").find("has an FMT but no records") != std::string::npos);
}

TEST(DataflashSignals, DamageLeavesTheOtherRecordsTheirValues) {
  const DataflashFile clean = ParseLog(testing::FlightLog());
  const DataflashFile damaged = ParseLog(testing::FlightLog("garbage"));
  ASSERT_FALSE(damaged.complete());
  EXPECT_EQ(SignalNames(damaged), SignalNames(clean));
  for (const std::string& name : SignalNames(clean)) {
    const timeseries::TimedSignal a = Extract(clean, name), b = Extract(damaged, name);
    EXPECT_EQ(a.t_s, b.t_s) << name;
    EXPECT_EQ(a.values, b.values) << name;
  }
}

}  // namespace
}  // namespace odonata::dataflash

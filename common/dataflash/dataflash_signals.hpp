#pragma once
// The numeric signals of a DataFlash log, by the names ArduPilot users write: "ATT.Pitch",
// "RATE.R", "RCOU.C3", "IMU.GyrX"; an element of an int16_t[32] field "ISBD.x[3]".
//
// Instances: a message whose FMTU marks a uint8 field as its instance number ('#': IMU's "I",
// XKF1's "C") gives one series per instance. Instance 0 is named plainly ("IMU.GyrX"), and also
// answers to "IMU[0].GyrX"; instance k >= 1 is "IMU[k].GyrX". The instance field itself is no
// signal. Logs without FMTU (before ArduPilot 4.0) log instances as messages of their own (IMU2).
//
// Values: the logged number times one multiplier. A scaled format character wins: c C e E are
// centi-units (× 0.01) and L is degrees × 1e7 (× 1e-7), as pymavlink reads them; ArduPilot pairs
// them with the FMTU multiplier of the same scale, and where FMTU says otherwise ('-' on XKF2.AX)
// the format character is what every tool applies. Any other numeric field is multiplied by its
// FMTU multiplier when the log gives one (MAG.MagX, logged in milligauss, × 0.001 is in gauss),
// so that the value is in the unit FMTU gives. The multiplier is no better than the firmware's
// metadata: ArduSub 4.1 labels CTUN.BAlt × 0.01 but logs it in metres.
//
// Time: seconds since boot, from the field "TimeUS" (µs) or, in older logs, "TimeMS" (ms); a
// message with neither has no signals. A record whose time is earlier than the one before it in
// the same message instance is dropped and counted in `out_of_order`: times are non-decreasing.
//
// Kinds: text fields (n N Z) are no signals. 8-bit integers (b B) and flight modes (M) are states
// and are held on a grid (timeseries::Interpolation::kHold); every other field is interpolated.

#include <cstddef>
#include <string>
#include <vector>

#include "dataflash/dataflash_file.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::dataflash {

struct SignalInfo {
  std::string name;              ///< "IMU[1].GyrX"
  std::string message;           ///< "IMU"
  int instance = -1;             ///< the instance number; -1 for a message without instance field
  std::string unit;              ///< FMTU's unit ("deg", "rad/s"); "" when the log gives none
  double multiplier = 1.0;       ///< what the logged number is multiplied by (see above)
  std::size_t samples = 0;       ///< kept records
  std::size_t out_of_order = 0;  ///< records dropped because their time went backwards
  /// 1 / the median interval between consecutive distinct times (0 with fewer than two): the
  /// rate the message was logged at, unmoved by a few long gaps.
  double median_rate_hz = 0.0;
  timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
};

/// Every numeric signal of the messages that have records and a time field, by message name,
/// instance and field order. Aliases ("IMU[0].GyrX") are not listed.
std::vector<SignalInfo> ListSignals(const DataflashFile& file);

/// The samples of signal `name`: times in seconds since boot, values scaled as above.
/// @throws std::invalid_argument for a name that is no signal of the file, saying why where it
///   can (a message without records, without time, a text field) and naming the 5 nearest names.
timeseries::TimedSignal Extract(const DataflashFile& file, const std::string& name);

}  // namespace odonata::dataflash

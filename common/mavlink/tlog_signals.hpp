#pragma once
// The numeric signals of a MAVLink telemetry log, by the names MAVLink users write:
// "ATTITUDE.pitchspeed", "SERVO_OUTPUT_RAW.servo3_raw", an element of an array field
// "ACTUATOR_OUTPUT_STATUS.actuator[1]" (elements from 0, as pymavlink indexes them).
//
// Senders: a message sent by several systems or components (HEARTBEAT from the vehicle, its
// camera and the ground station itself, which a .tlog records too) gives one series per sender.
// "MESSAGE@sysid:compid.field" names each ("ATTITUDE@1:1.pitch"); the plain name "MESSAGE.field"
// means the sender that sent most frames of the message (the lowest sysid, then compid, on a
// tie), which also answers to its own "@" name. Listed: the plain names, and the "@" names of the
// other senders. Only messages the table knows (mavlink_messages.hpp) and that have frames have
// signals.
//
// Time: seconds since the log's first record (TlogFile::first_time_us), from each frame's record
// timestamp, the time the ground station received it: the vehicle's own times (time_boot_ms,
// time_usec) are signals like any field. A frame timed earlier than the one before it of the same
// series is dropped and counted in `out_of_order`: times are non-decreasing.
//
// Kinds: uint8_t fields (modes, flags, ids, counts) are states, held on a grid
// (timeseries::Interpolation::kHold); every other field is interpolated. char fields are text,
// no signal.

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "mavlink/tlog_file.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::mavlink {

struct SignalInfo {
  std::string name;     ///< "ATTITUDE.pitchspeed", or "HEARTBEAT@1:1.custom_mode" (see above)
  std::string message;  ///< "ATTITUDE"
  std::uint8_t sysid = 0;
  std::uint8_t compid = 0;
  std::string field;             ///< "pitchspeed", "actuator[1]"
  std::string type;              ///< the C type: "float", "uint16_t", …
  std::size_t samples = 0;       ///< kept frames
  std::size_t out_of_order = 0;  ///< frames dropped because their time went backwards
  /// 1 / the median interval between consecutive distinct times (0 with fewer than two): the
  /// rate the message arrived at, unmoved by a few long gaps.
  double median_rate_hz = 0.0;
  timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
};

/// Every signal of the messages that have frames, by message name, sender (the plain names'
/// first) and field order (XML order, array elements in order).
std::vector<SignalInfo> ListSignals(const TlogFile& file);

/// The samples of signal `name` (a listed name, or a plain name's "@" alias), in seconds since
/// the log's first record; the signal's name is `name` as asked.
/// @throws std::invalid_argument for a name that is no signal of the file, saying why where it
///   can (a message the table does not know, one without frames, a sender that did not send it,
///   an array named without an index) and naming the 5 nearest names.
timeseries::TimedSignal Extract(const TlogFile& file, const std::string& name);

}  // namespace odonata::mavlink

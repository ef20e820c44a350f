#pragma once
// The numeric signals of a Crazyflie micro-SD log, by the names Crazyflie users write, each with
// its own times: what the resampler (timeseries/uniform_grid.hpp) puts on one grid.
//
// Names: a log variable by its own name, "gyro.x", "stateEstimate.z", "motor.m1"; a field of an
// event's payload (declared without a group) as "eventName.field", "estTDOA.distanceDiff".
// When several event types log the same name (gyro.x in estGyroscope and in the fixed-frequency
// block), the plain name is the one with the most records (the first declared, on a tie) and the
// others are "eventName:group.name" ("fixedFrequency:gyro.x"). "eventName:name" (the declared
// name: "estGyroscope:gyro.x", "estTDOA:distanceDiff") is always accepted. Only event types with
// records have signals; a variable an event type declares twice is one signal (the firmware reads
// the same variable twice into one record).
//
// Kinds: B and b (uint8_t, int8_t: flags, modes, ids) are states, held on a grid; every other
// code is interpolated.
//
// Time: seconds on the Crazyflie's clock (since it started), as logged, to the µs (version 1
// logs: to the ms). A record whose time is earlier than the one before it of the same event
// type (the firmware stamps a record before queuing it, so only tasks racing for the queue or
// corruption do this) is dropped and counted in `out_of_order`: times are then non-decreasing.

#include <cstddef>
#include <string>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "timeseries/uniform_grid.hpp"

namespace odonata::crazyflie_usd {

struct SignalInfo {
  std::string name;              ///< as listed: the plain name, or "eventName:name" (see above)
  std::string event;             ///< the event type's name: "estGyroscope", "fixedFrequency"
  std::string variable;          ///< as declared: "gyro.x", or a payload field "distanceDiff"
  std::string type;              ///< the C type: "float", "uint8_t", "half", …
  char code = 'f';               ///< the struct code: B b H h I i f e
  std::size_t samples = 0;       ///< kept records
  std::size_t out_of_order = 0;  ///< records dropped because their time went backwards
  /// 1 / the median interval between consecutive records of distinct times (0 with fewer than
  /// two): the rate the event was logged at, unmoved by a few long gaps.
  double median_rate_hz = 0.0;
  timeseries::Interpolation interpolation = timeseries::Interpolation::kLinear;
};

/// Every signal of the event types that have records, in the header's order of types and
/// variables.
std::vector<SignalInfo> ListSignals(const UsdLogFile& file);

/// The samples of signal `name` (a listed name, or "eventName:name"), in seconds on the
/// Crazyflie's clock; the signal's name is `name` as asked.
/// @throws std::invalid_argument for a name that is no signal of the file, naming the 5 nearest
///   ones (and saying when the name is declared by an event type that logged no record).
timeseries::TimedSignal Extract(const UsdLogFile& file, const std::string& name);

}  // namespace odonata::crazyflie_usd

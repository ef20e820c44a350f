#pragma once
// The learner's name for a finding about the data (timeseries/nothing_to_identify.hpp): what the
// excitation check and the series reader throw when the data holds nothing to identify.

#include "timeseries/nothing_to_identify.hpp"

namespace odonata::sysid {

using NothingToIdentify = timeseries::NothingToIdentify;
using timeseries::kNothingToIdentifyExit;

}  // namespace odonata::sysid

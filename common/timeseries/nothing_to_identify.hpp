#pragma once
// The data holds nothing a model can be identified from: a signal that never moves, a log too
// short for the lags, a window or condition that keeps nothing. Not a failure of the program but
// a finding about the data; odonata-fit and odonata-replay report it with what to do and exit
// with its own code (kNothingToIdentifyExit, docs/guide/offline-tool.md). Here, with the readers
// of logs, because a window or condition that keeps nothing is found while reading.

#include <stdexcept>
#include <string>

namespace odonata::timeseries {

class NothingToIdentify : public std::invalid_argument {
 public:
  explicit NothingToIdentify(const std::string& what) : std::invalid_argument(what) {}
};

/// The programs' exit code for it (1: an error, 2: a usage mistake).
inline constexpr int kNothingToIdentifyExit = 3;

}  // namespace odonata::timeseries

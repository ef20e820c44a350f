#pragma once
// The data holds nothing a model can be identified from: a signal that never moves, a log too
// short for the lags, a window or condition that keeps nothing. Not a failure of the program but
// a finding about the data; odonata-fit reports it with what to do and exits with its own code
// (kNothingToIdentifyExit, docs/guide/offline-tool.md).

#include <stdexcept>
#include <string>

namespace odonata::sysid {

class NothingToIdentify : public std::runtime_error {
 public:
  explicit NothingToIdentify(const std::string& what) : std::runtime_error(what) {}
};

/// odonata-fit's and odonata-replay's exit code for it (1: an error, 2: a usage mistake).
inline constexpr int kNothingToIdentifyExit = 3;

}  // namespace odonata::sysid

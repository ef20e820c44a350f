#include "vehicle/command_limits.hpp"

#include <cmath>
#include <cstdio>

namespace odonata::vehicle {

std::string CommandLimitProblems(const plant::CommandMatrix& command,
                                 const plant::ActuatorLimits& limits) {
  std::string problems;
  for (int w = 0; w < plant::kWingCount; ++w) {
    for (int i = 0; i < plant::kCommandsPerWing; ++i) {
      const double v = command(w, i);
      char line[160];
      if (!std::isfinite(v)) {
        std::snprintf(line, sizeof line, "%s is not finite",
                      plant::CommandColumnName(w, i).c_str());
      } else if (v < limits.min(i) || v > limits.max(i)) {
        std::snprintf(line, sizeof line, "%s = %.6g is outside its limits [%.6g, %.6g]",
                      plant::CommandColumnName(w, i).c_str(), v, limits.min(i), limits.max(i));
      } else {
        continue;
      }
      problems += (problems.empty() ? "" : "\n") + std::string(line);
    }
  }
  return problems;
}

}  // namespace odonata::vehicle

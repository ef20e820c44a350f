#pragma once
// The identifier's basic unit: sample k of a vehicle, its outputs y(k) and inputs u(k) in raw
// units, as the online identifier receives it and a Series holds it row by row.

#include <cstdint>

#include <Eigen/Core>

namespace odonata::sysid {

/// One sample as the online identifier receives it (raw units).
struct Sample {
  int64_t index = 0;  ///< k
  Eigen::VectorXd outputs;
  Eigen::VectorXd inputs;
};

}  // namespace odonata::sysid

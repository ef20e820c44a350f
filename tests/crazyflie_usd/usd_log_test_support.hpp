#pragma once
// Checks the micro-SD log tests share (one definition: the test files build as one unity source).

#include <gtest/gtest.h>

#include <cstddef>
#include <string>

#include "crazyflie_usd/usd_log_file.hpp"

namespace odonata::crazyflie_usd::testing {

inline bool Contains(const std::string& haystack, const std::string& needle) {
  return haystack.find(needle) != std::string::npos;
}

// Every record `part` read equals the same record of `whole`.
inline void ExpectRecordsOf(const UsdLogFile& part, const UsdLogFile& whole) {
  ASSERT_LE(part.event_types.size(), whole.event_types.size());
  for (std::size_t k = 0; k < part.event_types.size(); ++k) {
    const EventType& p = part.event_types[k];
    const EventType& w = whole.event_types[k];
    EXPECT_EQ(p.name, w.name);
    ASSERT_LE(p.size(), w.size());
    for (std::size_t i = 0; i < p.size(); ++i) {
      EXPECT_EQ(p.time_us[i], w.time_us[i]);
      for (std::size_t j = 0; j < p.variables.size(); ++j) EXPECT_EQ(p.Value(i, j), w.Value(i, j));
    }
  }
}

}  // namespace odonata::crazyflie_usd::testing

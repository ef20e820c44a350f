#pragma once
// The size of one event in a standard LCM event log (lcm_eventlog): a header of sync word, event
// number, timestamp, channel and data lengths, then the channel name and the data. The writer
// counts it to rotate files; the reader to tell a whole log from a damaged one.

#include <cstddef>
#include <cstdint>

namespace odonata::bus {

inline constexpr int64_t kLogEventHeaderBytes = 4 + 8 + 8 + 4 + 4;

constexpr int64_t LogEventBytes(std::size_t channel_bytes, int64_t data_bytes) {
  return kLogEventHeaderBytes + static_cast<int64_t>(channel_bytes) + data_bytes;
}

}  // namespace odonata::bus

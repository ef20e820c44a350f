#pragma once
// Reads standard LCM event logs to the end, and says so when it cannot: lcm::LogFile returns no
// event both at the end of a file and at a damaged event, so a reader that stops there would
// quietly export half a log.

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace odonata::bus {

/// What reading the logs found.
struct LogReadReport {
  long events = 0;         ///< events read whole
  int64_t bytes_lost = 0;  ///< bytes no whole event accounts for (damage, a cut-off end)
  int damaged_files = 0;   ///< files with such bytes
};

/// Calls `fn` for every readable event of every log, in order, and says what it could not read.
/// Damage — a last event cut off (its writer killed while writing it, a battery pulled), garbage
/// or an unreadable event in the middle — does not end the reading: the reader skips to the next
/// sync word that starts a well-formed event, and notes on stderr, once per file, how many bytes
/// were lost and where. `strict` makes any damage an error instead (odonata-logger export
/// --strict), before `fn` sees an event of the damaged file's remainder.
/// @throws std::runtime_error for a log that cannot be opened or stat'ed, or, when strict, one
///   that is damaged (naming the file, the byte offset and how many events were read).
LogReadReport ForEachLogEvent(const std::vector<std::string>& log_paths,
                              const std::function<void(const lcm::LogEvent&)>& fn,
                              bool strict = false);

}  // namespace odonata::bus

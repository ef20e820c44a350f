#pragma once
// Reads standard LCM event logs to the end, and says so when it cannot: lcm::LogFile returns no
// event both at the end of a file and at a damaged event, so a reader that stops there would
// quietly export half a log.

#include <functional>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace odonata::bus {

/// Calls `fn` for every event of every log, in order.
/// A log whose last event is cut off (its writer killed while writing it) is read up to that
/// event, with a note on stderr; anything else unreadable is an error.
/// @throws std::runtime_error for a log that cannot be opened, or that holds an unreadable event
///   before its end (naming the file, the byte offset and how many events were read).
void ForEachLogEvent(const std::vector<std::string>& log_paths,
                     const std::function<void(const lcm::LogEvent&)>& fn);

}  // namespace odonata::bus

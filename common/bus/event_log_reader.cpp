#include "bus/event_log_reader.hpp"

#include "bus/event_log_format.hpp"

#include <sys/stat.h>

#include <cstdint>
#include <cstdio>
#include <stdexcept>

namespace odonata::bus {

void ForEachLogEvent(const std::vector<std::string>& log_paths,
                     const std::function<void(const lcm::LogEvent&)>& fn) {
  for (const auto& path : log_paths) {
    lcm::LogFile log(path, "r");
    if (!log.good()) throw std::runtime_error(path + ": cannot open event log");
    struct stat st {};
    if (fstat(fileno(log.getFilePtr()), &st) != 0)
      throw std::runtime_error(path + ": cannot stat event log");
    // LogFile skips garbage until the next sync word, and stops at an event it cannot read as if
    // the file ended: only the bytes its events account for tell a whole log from a damaged one.
    int64_t good_bytes = 0;
    long events = 0;
    while (const lcm::LogEvent* ev = log.readNextEvent()) {
      if (ev->datalen < 0) break;
      good_bytes += LogEventBytes(ev->channel.size(), ev->datalen);
      ++events;
      fn(*ev);
    }
    if (good_bytes != static_cast<int64_t>(st.st_size)) {
      throw std::runtime_error(path + ": damaged event log: its " + std::to_string(events) +
                               " readable events hold " + std::to_string(good_bytes) + " of its " +
                               std::to_string(st.st_size) +
                               " bytes (an unreadable event, garbage, or a cut-off end)");
    }
  }
}

}  // namespace odonata::bus

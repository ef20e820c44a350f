#include "bus/event_log_reader.hpp"

#include "bus/event_log_format.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::bus {
namespace {

// The bytes from `offset` to the end are the start of one event that the file does not hold
// whole: its sync word, lengths that reach past the end (or a header cut short), and no other
// sync word after it — garbage before later events is damage, not a cut-off end.
bool CutOffEnd(FILE* f, int64_t offset, int64_t size) {
  const int64_t left = size - offset;
  if (left <= 0 || std::fseek(f, static_cast<long>(offset), SEEK_SET) != 0) return false;
  std::vector<unsigned char> rest(static_cast<std::size_t>(left));
  if (std::fread(rest.data(), 1, rest.size(), f) != rest.size()) return false;
  const unsigned char sync[4] = {0xED, 0xA1, 0xDA, 0x01};
  if (std::memcmp(rest.data(), sync, std::min<std::size_t>(rest.size(), 4)) != 0) return false;
  if (rest.size() > 4 &&
      std::search(rest.begin() + 1, rest.end(), std::begin(sync), std::end(sync)) != rest.end())
    return false;
  if (left < kLogEventHeaderBytes) return true;
  auto be32 = [&](int at) {
    return (uint32_t{rest[at]} << 24) | (uint32_t{rest[at + 1]} << 16) |
           (uint32_t{rest[at + 2]} << 8) | uint32_t{rest[at + 3]};
  };
  return LogEventBytes(be32(20), be32(24)) > left;
}

}  // namespace

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
    if (good_bytes != static_cast<int64_t>(st.st_size) &&
        CutOffEnd(log.getFilePtr(), good_bytes, static_cast<int64_t>(st.st_size))) {
      // A writer killed mid-event (kill -9, power loss): what came before is whole.
      static std::set<std::string> told;
      if (told.insert(path).second)
        std::fprintf(stderr,
                     "note: %s ends in a cut-off event (%lld bytes; its writer stopped while "
                     "writing it): the %ld whole events before it are read\n",
                     path.c_str(), static_cast<long long>(st.st_size - good_bytes), events);
    } else if (good_bytes != static_cast<int64_t>(st.st_size)) {
      throw std::runtime_error(path + ": damaged event log: its " + std::to_string(events) +
                               " readable events hold " + std::to_string(good_bytes) + " of its " +
                               std::to_string(st.st_size) +
                               " bytes (an unreadable event, garbage, or a cut-off end)");
    }
  }
}

}  // namespace odonata::bus

#include "bus/event_log_reader.hpp"

#include "bus/event_log_format.hpp"

#include <sys/stat.h>

#include <algorithm>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <memory>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::bus {
namespace {

constexpr unsigned char kSync[4] = {0xED, 0xA1, 0xDA, 0x01};

uint32_t Be32(const unsigned char* p) {
  return (uint32_t{p[0]} << 24) | (uint32_t{p[1]} << 16) | (uint32_t{p[2]} << 8) | uint32_t{p[3]};
}

// A header at `at` that lcm's reader can take without tripping its own checks (it asserts a
// channel shorter than 1000 bytes): a sync word, a channel of 1…255 bytes (LCM's limit is 63)
// and data that fits in the file.
bool PlausibleEvent(FILE* f, int64_t at, int64_t size) {
  if (size - at < kLogEventHeaderBytes) return false;
  unsigned char h[kLogEventHeaderBytes];
  if (std::fseek(f, static_cast<long>(at), SEEK_SET) != 0 ||
      std::fread(h, 1, sizeof h, f) != sizeof h)
    return false;
  if (std::memcmp(h, kSync, 4) != 0) return false;
  const uint32_t channel = Be32(h + 20), data = Be32(h + 24);
  return channel >= 1 && channel <= 255 && data <= 0x7fffffffu &&
         LogEventBytes(channel, data) <= size - at;
}

// The offset of the next plausible event at or after `from`, or `size` if there is none.
int64_t NextEvent(FILE* f, int64_t from, int64_t size) {
  std::vector<unsigned char> buf(1 << 16);
  for (int64_t at = from; at + 4 <= size;) {
    if (std::fseek(f, static_cast<long>(at), SEEK_SET) != 0) return size;
    const std::size_t n = std::fread(buf.data(), 1, buf.size(), f);
    if (n < 4) return size;
    for (std::size_t i = 0; i + 4 <= n; ++i)
      if (std::memcmp(buf.data() + i, kSync, 4) == 0 &&
          PlausibleEvent(f, at + static_cast<int64_t>(i), size))
        return at + static_cast<int64_t>(i);
    at += static_cast<int64_t>(n) - 3;  // a sync word may straddle two reads
  }
  return size;
}

}  // namespace

LogReadReport ForEachLogEvent(const std::vector<std::string>& log_paths,
                              const std::function<void(const lcm::LogEvent&)>& fn, bool strict) {
  LogReadReport report;
  for (const auto& path : log_paths) {
    // Read here, not with lcm::LogFile: LogFile skips garbage before a sync word silently, stops
    // at an unreadable event as if the file ended, drops a whole event that garbage follows, and
    // asserts on a channel length of 1000 or more. The format is lcm_eventlog's
    // (event_log_format.hpp), so lcm-logplayer and lcm-spy read the same files.
    const std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
    if (!file) throw std::runtime_error(path + ": cannot open event log");
    FILE* f = file.get();
    struct stat st {};
    if (fstat(fileno(f), &st) != 0) throw std::runtime_error(path + ": cannot stat event log");
    const auto size = static_cast<int64_t>(st.st_size);
    int64_t at = 0, lost = 0, first_damage = -1, last_damage = -1, last_damage_end = -1;
    long events = 0;
    auto damaged = [&](int64_t from, int64_t to) {
      if (to <= from) return;
      if (first_damage < 0) first_damage = from;
      last_damage = from;
      last_damage_end = to;
      lost += to - from;
      if (strict)
        throw std::runtime_error(path + ": damaged event log: " + std::to_string(to - from) +
                                 " unreadable bytes at byte " + std::to_string(from) +
                                 ", after its " + std::to_string(events) +
                                 " readable events (--strict)");
    };
    std::vector<unsigned char> buf;
    while (at < size) {
      const int64_t next = PlausibleEvent(f, at, size) ? at : NextEvent(f, at + 1, size);
      damaged(at, next);
      if (next >= size) break;
      // PlausibleEvent checked that the whole event lies in the file.
      unsigned char h[kLogEventHeaderBytes];
      if (std::fseek(f, static_cast<long>(next), SEEK_SET) != 0 ||
          std::fread(h, 1, sizeof h, f) != sizeof h)
        throw std::runtime_error(path + ": read error at byte " + std::to_string(next));
      const uint32_t channel_len = Be32(h + 20), data_len = Be32(h + 24);
      buf.resize(std::size_t{channel_len} + data_len);
      if (std::fread(buf.data(), 1, buf.size(), f) != buf.size())
        throw std::runtime_error(path + ": read error at byte " + std::to_string(next));
      lcm::LogEvent ev;
      ev.eventnum = static_cast<int64_t>((uint64_t{Be32(h + 4)} << 32) | Be32(h + 8));
      ev.timestamp = static_cast<int64_t>((uint64_t{Be32(h + 12)} << 32) | Be32(h + 16));
      ev.channel.assign(reinterpret_cast<const char*>(buf.data()), channel_len);
      ev.datalen = static_cast<int32_t>(data_len);
      ev.data = buf.data() + channel_len;
      ++events;
      fn(ev);
      at = next + LogEventBytes(channel_len, data_len);
    }
    report.events += events;
    if (lost > 0) {
      report.bytes_lost += lost;
      ++report.damaged_files;
      // A writer killed mid-event (kill -9, power loss) leaves one event's start at the end.
      bool cut_off = false;
      if (last_damage_end == size && std::fseek(f, static_cast<long>(last_damage), SEEK_SET) == 0) {
        unsigned char head[4] = {};
        const std::size_t n = std::fread(head, 1, 4, f);
        cut_off = n > 0 && std::memcmp(head, kSync, n) == 0;
      }
      static std::set<std::string> told;
      if (told.insert(path).second)
        std::fprintf(stderr,
                     "warning: %s is damaged: %lld of its %lld bytes are unreadable (from byte "
                     "%lld%s); its %ld readable events are read (odonata-logger export --strict "
                     "refuses such a log)\n",
                     path.c_str(), static_cast<long long>(lost), static_cast<long long>(size),
                     static_cast<long long>(first_damage),
                     cut_off ? "; it ends in a cut-off event: its writer stopped mid-event" : "",
                     events);
    }
  }
  return report;
}

}  // namespace odonata::bus

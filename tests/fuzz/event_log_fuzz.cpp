// Fuzz harness: the event-log reader (odonata-logger export's input, a file that may have been
// cut by a pulled battery or damaged on a card). Any bytes must be read without a crash, and
// every byte is either in an event read whole or counted as lost.
#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "bus/event_log_format.hpp"
#include "bus/event_log_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::string path =
      "/tmp/odonata_fuzz_event_log_" + std::to_string(static_cast<long>(getpid()));
  FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) return 0;
  std::fwrite(data, 1, size, f);
  std::fclose(f);
  int64_t read = 0;
  const auto report = odonata::bus::ForEachLogEvent({path}, [&read](const lcm::LogEvent& ev) {
    read += odonata::bus::LogEventBytes(ev.channel.size(), ev.datalen);
  });
  if (read + report.bytes_lost != static_cast<int64_t>(size)) std::abort();
  try {
    odonata::bus::ForEachLogEvent(
        {path}, [](const lcm::LogEvent&) {}, true);
    if (report.bytes_lost != 0) std::abort();  // strict read a damaged log as whole
  } catch (const std::runtime_error&) {
    if (report.bytes_lost == 0) std::abort();
  }
  std::remove(path.c_str());
  return 0;
}

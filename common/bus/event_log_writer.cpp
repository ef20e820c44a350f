#include "bus/event_log_writer.hpp"

#include <cstdio>
#include <stdexcept>

namespace odonata::bus {
namespace {
// lcm_eventlog's per-event header: sync word, event number, timestamp, channel and data lengths.
constexpr int64_t kEventHeaderBytes = 4 + 8 + 8 + 4 + 4;
}  // namespace

EventLogWriter::EventLogWriter(std::string prefix, int64_t split_bytes)
    : prefix_(std::move(prefix)), split_bytes_(split_bytes) {
  Open();
}

EventLogWriter::~EventLogWriter() {
  try {
    Close();
  } catch (...) {
  }
}

void EventLogWriter::Open() {
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, ".%05zu", files_.size());
  const std::string path = prefix_ + suffix;
  auto log = std::make_unique<lcm::LogFile>(path, "w");
  if (!log->good()) throw std::runtime_error(path + ": cannot create log file");
  log_ = std::move(log);
  files_.push_back(path);
  file_bytes_ = 0;
}

void EventLogWriter::Write(int64_t utime, const std::string& channel, const void* data,
                           int32_t size) {
  if (!log_) throw std::runtime_error(prefix_ + ": log already closed");
  const int64_t event_bytes = kEventHeaderBytes + static_cast<int64_t>(channel.size()) + size;
  if (split_bytes_ > 0 && file_bytes_ > 0 && file_bytes_ + event_bytes > split_bytes_) {
    Flush();
    log_.reset();
    Open();
  }
  lcm::LogEvent ev;
  ev.eventnum = 0;
  ev.timestamp = utime;
  ev.channel = channel;
  ev.datalen = size;
  ev.data = const_cast<void*>(data);  // LogFile's API is not const-correct; it only reads
  if (log_->writeEvent(&ev) != 0)
    throw std::runtime_error(files_.back() + ": write failed (disk full?)");
  file_bytes_ += event_bytes;
  total_bytes_ += event_bytes;
  ++events_;
}

void EventLogWriter::Flush() {
  if (log_ && std::fflush(log_->getFilePtr()) != 0) {
    throw std::runtime_error(files_.back() + ": flush failed (disk full?)");
  }
}

void EventLogWriter::Close() {
  if (!log_) return;
  Flush();
  log_.reset();
}

}  // namespace odonata::bus

#include "bus/event_log_writer.hpp"

#include "bus/event_log_format.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace odonata::bus {
namespace {
// LCM's own limit on channel names (LCM_MAX_CHANNEL_NAME_LENGTH).
constexpr std::size_t kMaxChannelBytes = 63;

std::string FileName(const std::string& prefix, int index) {
  char suffix[16];
  std::snprintf(suffix, sizeof suffix, ".%05d", index);
  return prefix + suffix;
}
}  // namespace

EventLogWriter::EventLogWriter(std::string prefix, int64_t split_bytes)
    : prefix_(std::move(prefix)), split_bytes_(split_bytes) {
  namespace fs = std::filesystem;
  const fs::path p(prefix_);
  const fs::path dir = p.has_parent_path() ? p.parent_path() : fs::path(".");
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir.string() + ": cannot create directory: " + ec.message());
  // Continue after the highest existing PREFIX.NNNNN.
  const std::string stem = p.filename().string();
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (name.size() != stem.size() + 6 || name.compare(0, stem.size(), stem) != 0 ||
        name[stem.size()] != '.')
      continue;
    const std::string digits = name.substr(stem.size() + 1);
    if (digits.find_first_not_of("0123456789") != std::string::npos) continue;
    next_index_ = std::max(next_index_, std::stoi(digits) + 1);
    ++earlier_files_;
  }
  Open();
}

EventLogWriter::~EventLogWriter() {
  try {
    Close();
  } catch (...) {
  }
}

void EventLogWriter::Open() {
  std::string path;
  for (;; ++next_index_) {
    if (next_index_ > 99999) throw std::runtime_error(prefix_ + ": no free log file number left");
    path = FileName(prefix_, next_index_);
    // Claimed exclusively, so neither an earlier recording nor a planted symlink is opened; the
    // LogFile below then opens the empty file this created.
    const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
      ::close(fd);
      break;
    }
    if (errno != EEXIST)
      throw std::runtime_error(path + ": cannot create log file: " + std::strerror(errno));
  }
  ++next_index_;
  auto log = std::make_unique<lcm::LogFile>(path, "w");
  if (!log->good()) throw std::runtime_error(path + ": cannot create log file");
  log_ = std::move(log);
  files_.push_back(path);
  file_bytes_ = 0;
}

void EventLogWriter::Write(int64_t utime, const std::string& channel, const void* data,
                           int32_t size) {
  if (!log_) throw std::runtime_error(prefix_ + ": log already closed");
  // Checked before writing: one bad event would make every later one unreadable.
  if (size < 0 || (data == nullptr && size > 0) || channel.empty() ||
      channel.size() > kMaxChannelBytes) {
    throw std::invalid_argument("malformed event on '" + channel.substr(0, kMaxChannelBytes) +
                                "' (" + std::to_string(size) + " bytes): not logged");
  }
  const int64_t event_bytes = LogEventBytes(channel.size(), size);
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

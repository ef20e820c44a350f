#pragma once
// Standard LCM event logs (readable by lcm-logplayer, lcm-spy and LogFile), rotated by size.

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <lcm/lcm-cpp.hpp>

namespace odonata::bus {

/// Writes events to PREFIX.00000, PREFIX.00001, … switching file when the current one exceeds
/// `split_bytes` (0 = never). Each event is written when it arrives; Flush() pushes the stdio
/// buffer to the kernel so a crash of this process loses at most the unflushed tail.
///
/// Never overwrites: a writer started on a prefix that already has files continues the numbering
/// after the highest one (a restarted logger keeps the earlier recording), and each file is
/// created exclusively, not through a symlink. Missing parent directories are created.
class EventLogWriter {
 public:
  /// @throws std::runtime_error if the first file cannot be created.
  EventLogWriter(std::string prefix, int64_t split_bytes);
  ~EventLogWriter();

  /// @throws std::runtime_error on a write error (disk full), naming the file;
  ///   std::invalid_argument for an event no reader could read back (negative size, no data,
  ///   an empty or over-long channel name), before anything is written.
  void Write(int64_t utime, const std::string& channel, const void* data, int32_t size);
  void Flush();
  void Close();

  const std::vector<std::string>& files() const { return files_; }
  /// Files of this prefix that were already there when the writer started (kept untouched).
  int earlier_files() const { return earlier_files_; }
  int64_t events() const { return events_; }
  int64_t bytes() const { return total_bytes_; }

 private:
  void Open();

  std::string prefix_;
  int64_t split_bytes_;
  std::unique_ptr<lcm::LogFile> log_;
  std::vector<std::string> files_;
  int next_index_ = 0;
  int earlier_files_ = 0;
  int64_t file_bytes_ = 0;
  int64_t total_bytes_ = 0;
  int64_t events_ = 0;
};

}  // namespace odonata::bus

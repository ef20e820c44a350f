#pragma once
// odonata-logger's recorder: every message on the chosen channels goes into a standard LCM
// event log as it arrives, undecoded, so a corrupt message is kept as evidence too.
//
// Inputs: every channel matching the regex. Outputs: log files; ODONATA_HEARTBEAT.

#include <cstdint>
#include <string>

#include "bus/ack_publisher.hpp"
#include "bus/bus_node.hpp"
#include "bus/event_log_writer.hpp"
#include "sequence/sample_sequence.hpp"
#include "sequence/written_run_marks.hpp"

namespace odonata::logger {

struct RecordOptions {
  std::string channels_regex = ".*";
  std::string prefix;       ///< files are PREFIX.00000, PREFIX.00001, …
  int64_t split_bytes = 0;  ///< rotate past this size (0: one file)
  /// At most this much is lost if the machine dies; what the logger acknowledges in lockstep is
  /// flushed before its receipt goes out, so a killed logger loses nothing acknowledged.
  double flush_period_s = 0.5;
  /// Disk budget (docs/lcm.md §12): past this many bytes in all files of this recording nothing
  /// more is written (0: none). Counted as dropped, said once on the heartbeat's state.
  int64_t max_bytes = 0;
  /// A message larger than this on one channel is not written (0: no limit): one forged 14 MB
  /// snapshot after another must not fill the disk. Counted as dropped, reported per channel.
  int64_t max_event_bytes = 0;
};

class LoggerNode {
 public:
  /// @throws std::runtime_error if the first log file cannot be created.
  LoggerNode(bus::BusNode& bus, const RecordOptions& options);
  const bus::EventLogWriter& writer() const { return writer_; }

 private:
  // Lockstep receipt (ack_t): the newest state written with its command and beat state, and
  // every earlier one with theirs.
  void Track(const std::string& channel, const lcm::ReceiveBuffer& rbuf);

  bus::BusNode& bus_;
  RecordOptions options_;
  bus::EventLogWriter writer_;
  WrittenRunMarks marks_;
  int64_t flushed_held_ = -1;  // the newest held state whose events were flushed
  bool over_budget_ = false;   // the disk budget is spent: nothing more is written
  bus::AckPublisher acks_;
  // signals_t samples (any vehicle's, or odonata-replay's): the newest written in order, by the
  // rule the export follows, acknowledged on the signals_ack channel.
  pipeline::SampleSequence signals_sequence_;
  bus::AckPublisher signal_acks_;
};

}  // namespace odonata::logger

#pragma once
// Counters every service reports in its heartbeat, and a log that prints each kind of problem
// once (a flood of corrupt messages must not become a flood of log lines).

#include <cstdint>
#include <set>
#include <string>

namespace odonata::bus {

struct ServiceStats {
  int64_t messages_in = 0;
  int64_t messages_out = 0;
  int64_t decode_errors = 0;  ///< undecodable: wrong fingerprint, truncated, garbage
  int64_t dropped = 0;        ///< decoded but rejected: NaN/Inf, out of range, duplicate, stale
  int64_t gaps = 0;           ///< sequence numbers skipped by a publisher
  int64_t skipped = 0;        ///< real time: commands superseded before any sample applied them
  int64_t repeated = 0;       ///< real time: extra samples applying an already applied command
  std::string last_error;
  std::string detail;  ///< what the service would tell its operator now (heartbeat_t::detail)

  /// Records a problem: sets last_error, and prints "[service] kind: message" to stderr the first
  /// time a problem of this shape is seen (the kind and the message with its numbers blanked:
  /// a second, different problem on a channel is printed too; the same one with other seqs is
  /// only counted). At most kMaxReportedShapes are printed in all.
  void Report(const std::string& service, const std::string& kind, const std::string& message);

 private:
  static constexpr std::size_t kMaxReportedShapes = 256;
  std::set<std::string> reported_shapes_;
};

}  // namespace odonata::bus

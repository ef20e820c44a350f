#pragma once
// Turns a recorded event log into the CSV odonata-sim writes (and odonata-fit reads): row k
// joins state k with the command the plant applied next (state k+1's command_seq).

#include <string>
#include <vector>

namespace odonata::bus {

struct ExportOptions {
  std::string command_channel = "DIMAV_COMMAND";
  std::string state_channel = "DIMAV_STATE";
  int run = -1;  ///< which run (a plant reset starts a new one); −1 = the last
};

struct ExportSummary {
  int runs = 0;           ///< runs found in the log(s)
  int exported_run = -1;  ///< the run written
  long rows = 0;
  long undecodable = 0;  ///< events on the two channels that did not decode (skipped)
  long incomplete = 0;   ///< states without a following state or matching command (gaps)
};

/// Reads the logs in order (a rotated log's files, oldest first) and writes `csv_path`.
/// @throws std::runtime_error naming the file on unreadable logs, no samples, or write errors.
ExportSummary ExportLogToCsv(const std::vector<std::string>& log_paths, const std::string& csv_path,
                             const ExportOptions& options);

}  // namespace odonata::bus

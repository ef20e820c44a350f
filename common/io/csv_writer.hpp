#pragma once
// Writes numeric CSV that CsvTable (and so odonata-fit) reads back exactly.

#include <fstream>
#include <string>
#include <vector>

namespace odonata::io {

/// Streams rows to a CSV file. Values are written with 17 significant digits so a round trip
/// through text is lossless (determinism across tools depends on it).
class CsvWriter {
 public:
  /// The header row first. No comment lines: every CSV reader (Python's csv.DictReader, pandas,
  /// Octave's csvread) reads the file as it is; what a reader should know goes to stderr.
  /// @throws std::runtime_error if the file cannot be created.
  CsvWriter(const std::string& path, const std::vector<std::string>& header);
  /// @pre row.size() == header size.
  void WriteRow(const std::vector<double>& row);
  /// Flushes and reports write errors (disk full) as std::runtime_error.
  void Close();
  ~CsvWriter();

 private:
  std::string path_;
  std::size_t columns_ = 0;
  std::ofstream out_;
};

}  // namespace odonata::io

#pragma once
// A numeric CSV table: a header row of column names, then one sample per row.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

namespace odonata::io {

/// A CSV larger than this (2 GiB) is refused: a device or a runaway file, not a flight log.
inline constexpr std::size_t kMaxCsvBytes = std::size_t{2} << 30;

/// Raised for any malformed input; the message names the file, line and column.
class CsvError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// What an empty cell or a NaN means: an error (the default), or a missing value kept as NaN for
/// the reader to bridge or cut out (sysid/series_from_table.hpp). Inf is an error either way.
enum class MissingCells { kReject, kKeepAsNaN };

/// How a file writes its cells: the separator between cells, and the decimal mark of numbers
/// (a spreadsheet in a German or French locale writes "1,5;2,25").
struct CsvFormat {
  char delimiter = ',';  ///< ',', ';' or '\t'
  char decimal = '.';    ///< '.' or ','; must differ from the delimiter
};

/// Column-major numeric table read from CSV. By default every cell must be a finite number, so
/// no model is ever trained on NaN or Inf.
class CsvTable {
 public:
  /// Reads `path`. Blank lines and lines starting with '#' are skipped.
  /// @throws CsvError naming the file, line and column of the first problem.
  static CsvTable Read(const std::string& path, MissingCells missing = MissingCells::kReject,
                       CsvFormat format = {});
  /// Parses CSV text; `source_name` is used in error messages.
  /// @throws std::invalid_argument when the format's delimiter and decimal mark are the same.
  static CsvTable Parse(const std::string& text, const std::string& source_name,
                        MissingCells missing = MissingCells::kReject, CsvFormat format = {});
  /// A table of columns made in memory (e.g. signals resampled from a flight log). The values are
  /// taken as they are: NaN marks a missing value, as MissingCells::kKeepAsNaN reads it.
  /// @throws CsvError naming `source` for a name that is empty or appears twice, or for a number
  ///   of names other than of columns, or columns of different lengths.
  static CsvTable FromColumns(std::string source, std::vector<std::string> names,
                              std::vector<std::vector<double>> columns);

  const std::vector<std::string>& names() const { return names_; }
  std::size_t rows() const { return columns_.empty() ? 0 : columns_.front().size(); }
  bool HasColumn(const std::string& name) const;
  /// @throws CsvError if the column does not exist, listing the ones that do.
  const std::vector<double>& Column(const std::string& name) const;
  const std::string& source() const { return source_; }

 private:
  std::string source_;
  std::vector<std::string> names_;
  std::vector<std::vector<double>> columns_;
};

}  // namespace odonata::io

#include "io/csv_table.hpp"

#include <algorithm>
#include <cctype>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <utility>

namespace odonata::io {
namespace {

std::string Trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t\r");
  if (b == std::string::npos) return "";
  const auto e = s.find_last_not_of(" \t\r");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> SplitCells(const std::string& line, char delimiter) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, delimiter)) cells.push_back(Trim(cell));
  if (!line.empty() && line.back() == delimiter) cells.emplace_back();
  return cells;
}

// What a header of one cell that holds another separator most likely means.
std::string DelimiterHint(const std::string& header, char delimiter) {
  for (const auto& [c, name] :
       {std::pair<char, const char*>{';', "';'"}, {'\t', "tab"}, {',', "','"}})
    if (c != delimiter && header.find(c) != std::string::npos)
      return std::string(" (its header is one cell holding ") + name +
             ": is the file separated by " + name + "? --delimiter " + name + ")";
  return "";
}

}  // namespace

CsvTable CsvTable::Read(const std::string& path, MissingCells missing, CsvFormat format) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw CsvError(path + ": cannot open file (" + std::strerror(errno) + ")");
  // Read in chunks with a cap, and refuse binary bytes early: /dev/zero or a device given by
  // mistake must end in an error, not in reading for ever.
  std::string text;
  std::vector<char> chunk(1 << 16);
  while (in.read(chunk.data(), static_cast<std::streamsize>(chunk.size())) || in.gcount() > 0) {
    const auto got = static_cast<std::size_t>(in.gcount());
    const auto end = chunk.begin() + static_cast<std::ptrdiff_t>(got);
    if (const auto nul = std::find(chunk.begin(), end, '\0'); nul != end)
      throw CsvError(path + ": a NUL byte at byte " +
                     std::to_string(text.size() + static_cast<std::size_t>(nul - chunk.begin())) +
                     ": a binary file, not a CSV");
    text.append(chunk.data(), got);
    if (text.size() > kMaxCsvBytes)
      throw CsvError(path + ": larger than " + std::to_string(kMaxCsvBytes >> 20) +
                     " MiB, more than a CSV this reader takes (cut it with odonata-fit --from/--to "
                     "after splitting it, or decimate it)");
  }
  return Parse(text, path, missing, format);
}

CsvTable CsvTable::Parse(const std::string& text, const std::string& source_name,
                         MissingCells missing, CsvFormat format) {
  if (format.delimiter == format.decimal)
    throw std::invalid_argument("the CSV delimiter and decimal mark must differ (both '" +
                                std::string(1, format.delimiter) + "')");
  CsvTable t;
  std::string header_line;
  t.source_ = source_name;
  std::istringstream in(text);
  std::string line;
  std::size_t line_no = 0;
  bool have_header = false;
  while (std::getline(in, line)) {
    ++line_no;
    const std::string trimmed = Trim(line);
    if (trimmed.empty() || trimmed.front() == '#') continue;
    auto cells = SplitCells(trimmed, format.delimiter);
    if (!have_header) {
      for (std::size_t c = 0; c < cells.size(); ++c) {
        if (cells[c].empty()) {
          throw CsvError(source_name + ":" + std::to_string(line_no) + ": column " +
                         std::to_string(c + 1) + " of the header has no name");
        }
        for (std::size_t p = 0; p < c; ++p) {
          if (cells[p] == cells[c]) {
            throw CsvError(source_name + ":" + std::to_string(line_no) + ": column name '" +
                           cells[c] + "' appears twice in the header (columns " +
                           std::to_string(p + 1) + " and " + std::to_string(c + 1) +
                           "): rename one of them in that line, e.g. to '" + cells[c] +
                           "_2', and name it so in --output or --input");
          }
        }
      }
      t.names_ = cells;
      header_line = trimmed;
      t.columns_.assign(cells.size(), {});
      have_header = true;
      continue;
    }
    if (cells.size() != t.names_.size()) {
      throw CsvError(source_name + ":" + std::to_string(line_no) + ": expected " +
                     std::to_string(t.names_.size()) + " cells, found " +
                     std::to_string(cells.size()) +
                     (t.names_.size() == 1 ? DelimiterHint(header_line, format.delimiter) : ""));
    }
    for (std::size_t c = 0; c < cells.size(); ++c) {
      const std::string where = source_name + ":" + std::to_string(line_no) + ": column " +
                                std::to_string(c + 1) + " ('" + t.names_[c] + "')";
      std::string cell = cells[c];
      if (format.decimal != '.') {
        // strtod reads the C locale's '.': a '.' in such a file is no decimal mark.
        if (cell.find('.') != std::string::npos)
          throw CsvError(where + ": '" + cell + "' is not a number with the decimal mark '" +
                         std::string(1, format.decimal) + "'");
        for (char& ch : cell)
          if (ch == format.decimal) ch = '.';
      }
      const bool keep = missing == MissingCells::kKeepAsNaN;
      if (cell.empty()) {
        if (!keep) throw CsvError(where + ": empty cell");
        t.columns_[c].push_back(std::nan(""));
        continue;
      }
      char* end = nullptr;
      errno = 0;
      const double v = std::strtod(cell.c_str(), &end);
      if (end == cell.c_str() || *end != '\0') {
        // One column whose cells hold another separator ("1.5;2" read with ','): most likely the
        // file's delimiter, which the message names with the option that reads it.
        throw CsvError(where + ": '" + cell + "' is not a number" +
                       (t.names_.size() == 1 ? DelimiterHint(header_line, format.delimiter) : ""));
      }
      if (std::isnan(v) && keep) {
        t.columns_[c].push_back(v);
        continue;
      }
      if (!std::isfinite(v)) throw CsvError(where + ": '" + cell + "' is not finite");
      t.columns_[c].push_back(v);
    }
  }
  if (!have_header) throw CsvError(source_name + ": no header row (the file is empty)");
  return t;
}

CsvTable CsvTable::FromColumns(std::string source, std::vector<std::string> names,
                               std::vector<std::vector<double>> columns) {
  if (names.size() != columns.size())
    throw CsvError(source + ": " + std::to_string(names.size()) + " column names for " +
                   std::to_string(columns.size()) + " columns");
  for (std::size_t c = 0; c < names.size(); ++c) {
    if (names[c].empty())
      throw CsvError(source + ": column " + std::to_string(c + 1) + " has no name");
    for (std::size_t p = 0; p < c; ++p)
      if (names[p] == names[c])
        throw CsvError(source + ": column name '" + names[c] + "' appears twice (columns " +
                       std::to_string(p + 1) + " and " + std::to_string(c + 1) + ")");
    if (columns[c].size() != columns.front().size())
      throw CsvError(source + ": column '" + names[c] + "' has " +
                     std::to_string(columns[c].size()) + " rows, column '" + names.front() + "' " +
                     std::to_string(columns.front().size()));
  }
  CsvTable t;
  t.source_ = std::move(source);
  t.names_ = std::move(names);
  t.columns_ = std::move(columns);
  return t;
}

bool CsvTable::HasColumn(const std::string& name) const {
  for (const auto& n : names_)
    if (n == name) return true;
  return false;
}

const std::vector<double>& CsvTable::Column(const std::string& name) const {
  for (std::size_t c = 0; c < names_.size(); ++c)
    if (names_[c] == name) return columns_[c];
  std::string have, same_letters;
  const auto lower = [](std::string s) {
    for (char& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
  };
  for (const auto& n : names_) {
    have += (have.empty() ? "" : ", ") + n;
    // Column names are case-sensitive; a name that differs only in case is what was meant.
    if (same_letters.empty() && lower(n) == lower(name)) same_letters = n;
  }
  throw CsvError(source_ + ": no column named '" + name + "'" +
                 (same_letters.empty() ? "" : " (did you mean '" + same_letters + "'?)") +
                 " (columns: " + have + ")");
}

}  // namespace odonata::io

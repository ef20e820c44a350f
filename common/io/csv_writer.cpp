#include "io/csv_writer.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>

namespace odonata::io {

CsvWriter::CsvWriter(const std::string& path, const std::vector<std::string>& header)
    : path_(path), columns_(header.size()), out_(path, std::ios::binary | std::ios::trunc) {
  if (!out_) throw std::runtime_error(path + ": cannot create file (" + std::strerror(errno) + ")");
  for (std::size_t i = 0; i < header.size(); ++i) out_ << (i ? "," : "") << header[i];
  out_ << '\n';
}

void CsvWriter::WriteRow(const std::vector<double>& row) {
  if (row.size() != columns_) {
    throw std::logic_error(path_ + ": row has " + std::to_string(row.size()) + " values, header " +
                           std::to_string(columns_));
  }
  char buf[32];
  for (std::size_t i = 0; i < row.size(); ++i) {
    std::snprintf(buf, sizeof buf, "%.17g", row[i]);
    if (i) out_ << ',';
    out_ << buf;
  }
  out_ << '\n';
}

void CsvWriter::Close() {
  if (!out_.is_open()) return;
  out_.flush();
  const bool ok = static_cast<bool>(out_);
  out_.close();
  if (!ok) throw std::runtime_error(path_ + ": write failed (disk full?)");
}

CsvWriter::~CsvWriter() {
  if (out_.is_open()) out_.close();
}

}  // namespace odonata::io

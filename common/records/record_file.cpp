#include "records/record_file.hpp"

#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

namespace odonata::records {

bool IsUlog(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  char magic[7] = {};
  in.read(magic, sizeof magic);
  return in.gcount() == 7 && std::string(magic, 4) == "ULog" && magic[4] == 0x01 &&
         magic[5] == 0x12 && magic[6] == 0x35;
}

namespace {

Record ReadUlog(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty())
    throw std::invalid_argument(path +
                                ": a ULog holds hundreds of signals; name the ones to take "
                                "(odonata-ulog topics " +
                                path + " lists them)");
  const ulog::UlogFile file = ulog::Read(path);
  Record r;
  if (!file.complete()) {
    char where[64];
    std::snprintf(where, sizeof where, "%llu",
                  static_cast<unsigned long long>(file.problem_offset));
    r.warnings.push_back(path + ": damaged at byte " + where + " (" + file.problem +
                         "); what was logged before it is used");
  }
  ulog::ResampledSignals s;
  try {
    s = ulog::Resample(file, o.signals, o.rate_hz, o.max_gap);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
  std::vector<std::string> names{"t_s"};
  std::vector<std::vector<double>> columns{s.t_s};
  for (std::size_t k = 0; k < s.names.size(); ++k) {
    names.push_back(s.names[k]);
    columns.push_back(std::move(s.columns[k]));
    if (s.out_of_order[k] > 0)
      r.warnings.push_back(path + ": " + s.names[k] + ": " + std::to_string(s.out_of_order[k]) +
                           " samples dropped, their time went backwards");
    if (s.gap_cells[k] > 0)
      r.warnings.push_back(path + ": " + s.names[k] + ": " + std::to_string(s.gap_cells[k]) +
                           " of " + std::to_string(s.t_s.size()) +
                           " grid samples fall in gaps longer than the gap rule bridges");
  }
  r.table = io::CsvTable::FromColumns(path, std::move(names), std::move(columns));
  r.time_column = "t_s";
  r.rate_hz = s.rate_hz;
  return r;
}

}  // namespace

Record ReadRecord(const std::string& path, const RecordOptions& options) {
  if (IsUlog(path)) return ReadUlog(path, options);
  Record r{io::CsvTable::Read(path, options.missing, options.csv_format), "", 0, {}};
  return r;
}

}  // namespace odonata::records

#include "records/record_file.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "crazyflie_usd/usd_log_file.hpp"
#include "crazyflie_usd/usd_log_signals.hpp"
#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"
#include "records/record_grid.hpp"
#include "timeseries/nothing_to_identify.hpp"
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

std::string NameThem(const std::string& path, const char* what) {
  return path + ": " + what + " holds many signals; name the ones to take (odonata-log topics " +
         path + " lists them)";
}

std::string DamageWarning(const std::string& path, std::uint64_t offset,
                          const std::string& problem) {
  return path + ": damaged at byte " + std::to_string(offset) + " (" + problem +
         "); what was read apart from it is used";
}

Record ReadUlog(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty()) throw std::invalid_argument(NameThem(path, "a ULog"));
  const ulog::UlogFile file = ulog::Read(path);
  Record r;
  if (!file.complete()) {
    char where[64];
    std::snprintf(where, sizeof where, "%llu",
                  static_cast<unsigned long long>(file.problem_offset));
    r.warnings.push_back(path + ": damaged at byte " + where + " (" + file.problem +
                         "); what was logged before it is used");
  }
  const std::vector<std::string> signals = SignalsToRead(o);
  timeseries::GridOptions grid;
  grid.rate_hz = o.rate_hz;
  grid.max_gap = o.max_gap;
  grid.from_s = o.from_s;
  grid.to_s = o.to_s;
  ulog::ResampledSignals s;
  try {
    s = ulog::Resample(
        file, signals, grid,
        o.keep ? std::vector<std::string>{o.keep->signal} : std::vector<std::string>{});
  } catch (const timeseries::NothingToIdentify& e) {
    throw timeseries::NothingToIdentify(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    if (o.keep && std::string(e.what()).find("'" + o.keep->signal + "'") != std::string::npos)
      throw std::invalid_argument(path + ": the condition " + o.keep->ToString() +
                                  " cannot be read: " + e.what() +
                                  "; name another signal to keep by (--keep-when)");
    throw std::invalid_argument(path + ": " + e.what());
  }
  SignalsOnGrid g;
  g.rate_hz = s.rate_hz;
  g.rate_chosen = s.rate_chosen;
  g.t_s = std::move(s.t_s);
  g.names = std::move(s.names);
  g.columns = std::move(s.columns);
  g.median_rate_hz = std::move(s.median_rate_hz);
  g.interpolation = std::move(s.interpolation);
  g.gap_cells = std::move(s.gap_cells);
  g.out_of_order = std::move(s.out_of_order);
  return RecordFromGrid(path, std::move(g), o.max_gap, std::move(r));
}

// A log read by its own reader (`Parse`) and named signals (`Extract`), put on the shared grid.
template <class File, class ExtractFn>
Record ReadSignalLog(const std::string& path, const RecordOptions& o, const File& file,
                     ExtractFn extract, Record r) {
  std::vector<timeseries::TimedSignal> timed;
  for (const auto& name : SignalsToRead(o)) {
    try {
      timed.push_back(extract(file, name));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(path + ": " + e.what());
    }
    // A condition's signal is a state of the flight: held, and it does not choose the grid.
    if (o.keep && name == o.keep->signal)
      timed.back().interpolation = timeseries::Interpolation::kHold;
  }
  try {
    SignalsOnGrid g = ResampleSignals(timed, {}, o);
    return RecordFromGrid(path, std::move(g), o.max_gap, std::move(r));
  } catch (const timeseries::NothingToIdentify& e) {
    throw timeseries::NothingToIdentify(path + ": " + e.what());
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(path + ": " + e.what());
  }
}

Record ReadDataflash(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty()) throw std::invalid_argument(NameThem(path, "a DataFlash log"));
  const dataflash::DataflashFile file = dataflash::Read(path);
  Record r;
  if (!file.complete())
    r.warnings.push_back(DamageWarning(path, file.problem_offset, file.problem));
  return ReadSignalLog(path, o, file, dataflash::Extract, std::move(r));
}

Record ReadTlog(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty()) throw std::invalid_argument(NameThem(path, "a MAVLink telemetry log"));
  const mavlink::TlogFile file = mavlink::Read(path);
  Record r;
  if (!file.complete())
    r.warnings.push_back(DamageWarning(path, file.problem_offset, file.problem));
  for (const auto& n : file.notes) r.warnings.push_back(path + ": " + n);
  return ReadSignalLog(path, o, file, mavlink::Extract, std::move(r));
}

Record ReadUsdLog(const std::string& path, const RecordOptions& o) {
  if (o.signals.empty()) throw std::invalid_argument(NameThem(path, "a Crazyflie micro-SD log"));
  const crazyflie_usd::UsdLogFile file = crazyflie_usd::Read(path);
  Record r;
  if (!file.complete())
    r.warnings.push_back(DamageWarning(path, file.problem_offset, file.problem));
  for (const auto& n : file.notes) r.warnings.push_back(path + ": " + n);
  return ReadSignalLog(path, o, file, crazyflie_usd::Extract, std::move(r));
}

}  // namespace

RecordFormat DetectFormat(const std::string& path) {
  if (IsUlog(path)) return RecordFormat::kUlog;
  std::ifstream in(path, std::ios::binary);
  std::string head(16, '\0');
  in.read(head.data(), static_cast<std::streamsize>(head.size()));
  head.resize(static_cast<std::size_t>(in.gcount()));
  if (dataflash::LooksLikeDataflash(head)) return RecordFormat::kDataflash;
  if (crazyflie_usd::LooksLikeUsdLog(head)) return RecordFormat::kCrazyflieUsd;
  if (mavlink::LooksLikeTlog(head)) return RecordFormat::kMavlinkTlog;
  return RecordFormat::kCsv;
}

const char* FormatName(RecordFormat format) {
  switch (format) {
    case RecordFormat::kUlog:
      return "PX4 ULog";
    case RecordFormat::kDataflash:
      return "ArduPilot DataFlash";
    case RecordFormat::kCrazyflieUsd:
      return "Crazyflie micro-SD";
    case RecordFormat::kMavlinkTlog:
      return "MAVLink telemetry log";
    case RecordFormat::kCsv:
      break;
  }
  return "CSV";
}

Record ReadRecord(const std::string& path, const RecordOptions& options) {
  switch (DetectFormat(path)) {
    case RecordFormat::kUlog:
      return ReadUlog(path, options);
    case RecordFormat::kDataflash:
      return ReadDataflash(path, options);
    case RecordFormat::kCrazyflieUsd:
      return ReadUsdLog(path, options);
    case RecordFormat::kMavlinkTlog:
      return ReadTlog(path, options);
    case RecordFormat::kCsv:
      break;
  }
  return Record{io::CsvTable::Read(path, options.missing, options.csv_format), "", 0, {}, {}};
}

}  // namespace odonata::records

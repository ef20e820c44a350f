#include "log_topics.hpp"

#include <cstdio>
#include <stdexcept>
#include <string>
#include <vector>

#include "crazyflie_usd/usd_log_file.hpp"
#include "crazyflie_usd/usd_log_signals.hpp"
#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"
#include "mavlink/tlog_file.hpp"
#include "mavlink/tlog_signals.hpp"
#include "records/record_file.hpp"
#include "ulog/ulog_file.hpp"
#include "ulog/ulog_signals.hpp"

namespace {

bool Shown(const std::string& name, const std::string& match) {
  return match.empty() || name.find(match) != std::string::npos;
}

void Footer(std::size_t shown, std::size_t all, const std::string& match) {
  std::printf("%zu of %zu signals%s\n", shown, all,
              match.empty() ? "" : (" matching '" + match + "'").c_str());
}

void Damage(bool complete, unsigned long long offset, const std::string& problem) {
  if (!complete)
    std::printf("  DAMAGED at byte %llu: %s (what came before is listed)\n", offset,
                problem.c_str());
}

int UlogTopics(const std::string& path, const std::string& match) {
  const odonata::ulog::UlogFile f = odonata::ulog::Read(path);
  const auto signals = odonata::ulog::ListSignals(f);
  std::size_t data = 0;
  for (const auto& s : f.subscriptions) data += s.timestamps_us.size();
  std::printf(
      "%s: ULog version %d, %zu bytes, %zu topics logged (%zu data messages), %zu "
      "parameters, %zu log messages, %zu dropouts (%llu ms)%s\n",
      path.c_str(), f.version, f.file_size, f.subscriptions.size(), data,
      f.initial_parameters.size(), f.log_messages.size(), f.dropouts.size(),
      static_cast<unsigned long long>(f.dropout_total_ms),
      f.appended_messages ? ", appended data" : "");
  if (!f.complete())
    std::printf("  DAMAGED at byte %llu: %s (what came before is listed)\n",
                static_cast<unsigned long long>(f.problem_offset), f.problem.c_str());
  for (const auto& n : f.notes) std::printf("  note: %s\n", n.c_str());
  std::printf("%-56s %-9s %8s %10s %10s\n", "signal", "type", "samples", "median Hz", "mean Hz");
  std::size_t shown = 0;
  for (const auto& s : signals) {
    if (!match.empty() && s.name.find(match) == std::string::npos) continue;
    std::printf(
        "%-56s %-9s %8zu %10.2f %10.2f%s\n", s.name.c_str(), s.type.c_str(), s.samples,
        s.median_rate_hz, s.mean_rate_hz,
        s.out_of_order ? (" (" + std::to_string(s.out_of_order) + " out of order)").c_str() : "");
    ++shown;
  }
  std::printf("%zu of %zu signals%s\n", shown, signals.size(),
              match.empty() ? "" : (" matching '" + match + "'").c_str());
  return 0;
}

int DataflashTopics(const std::string& path, const std::string& match) {
  const odonata::dataflash::DataflashFile f = odonata::dataflash::Read(path);
  const auto signals = odonata::dataflash::ListSignals(f);
  std::printf("%s: ArduPilot DataFlash, %zu bytes, %zu message formats\n", path.c_str(),
              f.file_size, f.formats.size());
  Damage(f.complete(), static_cast<unsigned long long>(f.problem_offset), f.problem);
  std::printf("%-40s %-10s %8s %10s\n", "signal", "unit", "samples", "median Hz");
  std::size_t shown = 0;
  for (const auto& s : signals) {
    if (!Shown(s.name, match)) continue;
    std::printf("%-40s %-10s %8zu %10.2f\n", s.name.c_str(), s.unit.empty() ? "-" : s.unit.c_str(),
                s.samples, s.median_rate_hz);
    ++shown;
  }
  Footer(shown, signals.size(), match);
  return 0;
}

int UsdTopics(const std::string& path, const std::string& match) {
  const odonata::crazyflie_usd::UsdLogFile f = odonata::crazyflie_usd::Read(path);
  const auto signals = odonata::crazyflie_usd::ListSignals(f);
  std::printf("%s: Crazyflie micro-SD, version %d, %zu bytes, %zu event types, CRC %s\n",
              path.c_str(), static_cast<int>(f.version), f.file_size, f.event_types.size(),
              f.crc_valid ? "valid" : "NOT valid");
  Damage(f.complete(), static_cast<unsigned long long>(f.problem_offset), f.problem);
  for (const auto& n : f.notes) std::printf("  note: %s\n", n.c_str());
  std::printf("%-40s %-9s %8s %10s\n", "signal", "type", "samples", "median Hz");
  std::size_t shown = 0;
  for (const auto& s : signals) {
    if (!Shown(s.name, match)) continue;
    std::printf("%-40s %-9s %8zu %10.2f\n", s.name.c_str(), s.type.c_str(), s.samples,
                s.median_rate_hz);
    ++shown;
  }
  Footer(shown, signals.size(), match);
  return 0;
}

int TlogTopics(const std::string& path, const std::string& match) {
  const odonata::mavlink::TlogFile f = odonata::mavlink::Read(path);
  const auto signals = odonata::mavlink::ListSignals(f);
  std::printf("%s: MAVLink telemetry log, %zu bytes\n", path.c_str(), f.file_size);
  Damage(f.complete(), static_cast<unsigned long long>(f.problem_offset), f.problem);
  for (const auto& n : f.notes) std::printf("  note: %s\n", n.c_str());
  std::printf("%-48s %-9s %8s %10s\n", "signal", "type", "samples", "median Hz");
  std::size_t shown = 0;
  for (const auto& s : signals) {
    if (!Shown(s.name, match)) continue;
    std::printf("%-48s %-9s %8zu %10.2f\n", s.name.c_str(), s.type.c_str(), s.samples,
                s.median_rate_hz);
    ++shown;
  }
  Footer(shown, signals.size(), match);
  return 0;
}

}  // namespace

int Topics(const std::string& path, const std::string& match) {
  switch (odonata::records::DetectFormat(path)) {
    case odonata::records::RecordFormat::kUlog:
      return UlogTopics(path, match);
    case odonata::records::RecordFormat::kDataflash:
      return DataflashTopics(path, match);
    case odonata::records::RecordFormat::kCrazyflieUsd:
      return UsdTopics(path, match);
    case odonata::records::RecordFormat::kMavlinkTlog:
      return TlogTopics(path, match);
    case odonata::records::RecordFormat::kCsv:
      break;
  }
  throw std::runtime_error(
      path +
      " is no flight log this tool reads (not a PX4 ULog, an ArduPilot "
      "DataFlash log, a Crazyflie micro-SD log or a MAVLink .tlog, by its first bytes)");
}

// Fuzz harness: the DataFlash reader (ArduPilot flight logs) and its signals. Damage must end in
// the file's `problem` (the walk resynchronising on the next record header), what is no DataFlash
// log in odonata::dataflash::DataflashError, a signal that cannot be had in std::invalid_argument:
// never a crash, undefined behaviour or unbounded memory.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include "dataflash/dataflash_file.hpp"
#include "dataflash/dataflash_signals.hpp"

namespace {

void Check(bool ok) {
  if (!ok) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  namespace df = odonata::dataflash;
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  try {
    const df::DataflashFile file = df::Parse(bytes, "fuzz");
    Check(file.complete() == file.problem.empty());
    Check(file.complete() == (file.damage_count == 0));
    Check(file.problem_offset <= size);
    Check(file.bytes_skipped <= size);
    Check(file.file_size == size && file.bytes == bytes);
    std::size_t records = 0;
    for (const auto& [type, n] : file.record_counts) {
      Check(file.formats.count(type) == 1);
      records += n;
    }
    // Every kept record lies whole in the file, under its own type, named by its format.
    std::size_t kept = 0;
    for (const auto& [name, m] : file.messages) {
      const auto it = file.formats.find(m.type);
      Check(it != file.formats.end() && it->second.name == name);
      for (const std::uint64_t offset : m.offsets)
        Check(offset + it->second.length <= size &&
              static_cast<std::uint8_t>(file.bytes[offset + 2]) == m.type);
      kept += m.size();
    }
    Check(kept <= records);
    for (const auto& [type, format] : file.formats) {
      Check(format.length >= df::kRecordHeaderSize);
      Check(format.decodable() || format.fields.empty());
      for (std::size_t i = 0; i < format.fields.size(); ++i) {
        (void)file.UnitOf(format, i);
        (void)file.MultiplierOf(format, i);
      }
      (void)file.InstanceField(format);
    }
    const std::vector<df::SignalInfo> signals = df::ListSignals(file);
    for (std::size_t i = 0; i < signals.size(); i += 1 + signals.size() / 4) {
      const odonata::timeseries::TimedSignal s = df::Extract(file, signals[i].name);
      Check(s.t_s.size() == s.values.size() && s.values.size() == signals[i].samples);
      Check(std::is_sorted(s.t_s.begin(), s.t_s.end()));
      Check(s.interpolation == signals[i].interpolation);
    }
    (void)df::Extract(file, "NO[1].such[0]");
  } catch (const odonata::dataflash::DataflashError&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

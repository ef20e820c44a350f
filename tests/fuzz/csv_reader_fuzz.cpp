// Fuzz harness: the CSV reader (odonata-fit's and the exporter's input). Bad text must end in
// std::runtime_error or std::invalid_argument, never in a crash or undefined behaviour.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "io/csv_table.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const auto table = odonata::io::CsvTable::Parse(text, "fuzz");
    for (const auto& name : table.names()) (void)table.Column(name);
  } catch (const std::runtime_error&) {
  } catch (const std::invalid_argument&) {
  }
  return 0;
}

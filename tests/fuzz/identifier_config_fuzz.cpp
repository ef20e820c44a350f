// Fuzz harness: odonata-identifier's configuration file. Every bad file is a runtime_error
// listing its problems.
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

#include "identifier_config/identifier_config.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)odonata::identifier::ParseIdentifierConfig(
        std::string(reinterpret_cast<const char*>(data), size), "fuzz");
  } catch (const std::runtime_error&) {
  }
  return 0;
}

#pragma once
// Numbers in exported model files: 17 significant digits, so every client that reads the text
// back (Octave, fuzzylite, inference/odonata/tsk_model.hpp) gets the same double.

#include <cstdio>
#include <string>

namespace odonata::model_export {

inline std::string ExactNumber(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

}  // namespace odonata::model_export

#include "bus/service_stats.hpp"

#include <cstdio>

namespace odonata::bus {

namespace {
// The problem without its numbers: "state seq 12 leaps 900000 past …" and "state seq 13 leaps
// 900001 past …" are one problem, "… seq 12 leaps …" and "duplicate … seq 12" are two.
std::string Shape(const std::string& kind, const std::string& message) {
  std::string shape = kind + ": ";
  bool in_number = false;
  for (const char c : message) {
    const bool digit = c >= '0' && c <= '9';
    if (digit && !in_number) shape += '#';
    if (!digit) shape += c;
    in_number = digit;
  }
  return shape;
}
}  // namespace

void ServiceStats::Report(const std::string& service, const std::string& kind,
                          const std::string& message) {
  last_error = kind + ": " + message;
  // Bounded: forged messages can carry endless different text.
  if (reported_shapes_.size() >= kMaxReportedShapes) return;
  if (reported_shapes_.insert(Shape(kind, message)).second) {
    std::fprintf(stderr, "[%s] %s: %s (further problems like this are only counted)\n",
                 service.c_str(), kind.c_str(), message.c_str());
  }
}

}  // namespace odonata::bus

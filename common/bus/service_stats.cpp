#include "bus/service_stats.hpp"

#include <cstdio>

namespace odonata::bus {

void ServiceStats::Report(const std::string& service, const std::string& kind,
                          const std::string& message) {
  last_error = kind + ": " + message;
  if (reported_kinds_.insert(kind).second) {
    std::fprintf(stderr, "[%s] %s: %s (further problems of this kind are only counted)\n",
                 service.c_str(), kind.c_str(), message.c_str());
  }
}

}  // namespace odonata::bus

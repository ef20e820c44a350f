#include "bus/udpm_endpoint.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <cstdlib>

namespace odonata::bus {

std::string EffectiveLcmUrl(const std::string& url) {
  if (!url.empty()) return url;
  const char* env = std::getenv("LCM_DEFAULT_URL");
  if (env != nullptr && *env != '\0') return env;
  return "udpm://239.255.76.67:7667?ttl=0";
}

std::optional<UdpmEndpoint> ParseUdpmEndpoint(const std::string& url) {
  const std::string scheme = "udpm://";
  if (url.compare(0, scheme.size(), scheme) != 0) return std::nullopt;
  const std::string rest = url.substr(scheme.size());
  const std::size_t q = rest.find('?');
  const std::string network = rest.substr(0, q);
  UdpmEndpoint e;
  if (!network.empty()) {
    const std::size_t colon = network.find(':');
    if (colon == std::string::npos) return std::nullopt;  // LCM would bind port 0
    e.group = network.substr(0, colon);
    in_addr addr{};
    if (inet_aton(e.group.c_str(), &addr) == 0) return std::nullopt;
    const std::string port = network.substr(colon + 1);
    char* end = nullptr;
    const long p = std::strtol(port.c_str(), &end, 0);
    if (port.empty() || *end != '\0' || p <= 0 || p > 65535) return std::nullopt;
    e.port = static_cast<uint16_t>(p);
  }
  if (q == std::string::npos) return e;
  std::string options = rest.substr(q + 1);
  std::size_t start = 0;
  while (start <= options.size()) {
    const std::size_t amp = std::min(options.find('&', start), options.size());
    const std::string kv = options.substr(start, amp - start);
    const std::size_t eq = kv.find('=');
    const std::string key = eq == std::string::npos ? kv : kv.substr(0, eq);
    if (eq != std::string::npos && (key == "recv_buf_size" || key == "ttl")) {
      char* end = nullptr;
      const long v = std::strtol(kv.c_str() + eq + 1, &end, 0);
      if (*end != '\0' || v < 0 || v > (key == "ttl" ? 255L : 1L << 30)) return std::nullopt;
      (key == "ttl" ? e.ttl : e.recv_buf_size) = static_cast<int>(v);
    }
    start = amp + 1;
  }
  return e;
}

}  // namespace odonata::bus

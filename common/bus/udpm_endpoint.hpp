#pragma once
// Where an LCM udpm URL receives: its multicast group, port and receive buffer, read the way
// LCM 1.3.1 reads them (docs/lcm.md §9), so odonata's own receiver joins the same bus as LCM's
// tools.

#include <cstdint>
#include <optional>
#include <string>

namespace odonata::bus {

struct UdpmEndpoint {
  std::string group = "239.255.76.67";
  uint16_t port = 7667;
  int recv_buf_size = 0;  ///< bytes; 0 keeps the kernel's default
  int ttl = 0;            ///< multicast hops for what this process sends (LCM's default: 0)
};

/// The URL LCM opens for `url`: itself, or when empty $LCM_DEFAULT_URL, else LCM's default.
std::string EffectiveLcmUrl(const std::string& url);

/// The endpoint of a udpm URL (after EffectiveLcmUrl). Empty for other providers (memq://,
/// file://) and for udpm forms this parser leaves to LCM (no port, a host name): those keep
/// LCM's own receive path.
std::optional<UdpmEndpoint> ParseUdpmEndpoint(const std::string& url);

}  // namespace odonata::bus

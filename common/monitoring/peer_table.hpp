#pragma once
// odonata-monitor's view of the other services without transport: their last heartbeat, which
// went silent, which came back, and a real-time plant falling behind. Each call returns what the
// operator should hear of; the shell prints it.

#include <chrono>
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace odonata::monitoring {

/// One heartbeat_t, as the table needs it.
struct Heartbeat {
  std::string instance, service, state;
  int64_t decode_errors = 0, dropped = 0, gaps = 0, skipped = 0, repeated = 0;
  std::string detail =
      {};  ///< heartbeat_t::detail: e.g. whether the identifier's model has seen enough
};

struct PeerEvent {
  enum class Kind {
    kBack,           ///< a silent service is heard again
    kFallingBehind,  ///< a real-time plant skipped or repeated more commands (the new totals)
    kSilent,         ///< no heartbeat for `silent_s`
  };
  Kind kind = Kind::kBack;
  std::string instance, service, state;
  int64_t skipped = 0, repeated = 0;
  double silent_s = 0;
};

class PeerTable {
 public:
  using Clock = std::chrono::steady_clock;
  static constexpr std::size_t kMaxPeers = 256;  ///< the least recently heard is forgotten

  struct Peer {
    Heartbeat last;
    Clock::time_point last_seen;
    bool silent = false;
  };

  std::vector<PeerEvent> OnHeartbeat(const Heartbeat& hb, Clock::time_point now);
  /// Services silent for more than `timeout_s` (each said once, until heard again); a service
  /// that said it is stopping is not missed.
  std::vector<PeerEvent> CheckSilence(Clock::time_point now, double timeout_s);

  const std::map<std::string, Peer>& peers() const { return peers_; }
  /// {instance: {service, state, decode_errors, dropped, gaps, skipped, repeated}}.
  nlohmann::json Summary() const;

 private:
  std::map<std::string, Peer> peers_;  // by instance
};

}  // namespace odonata::monitoring

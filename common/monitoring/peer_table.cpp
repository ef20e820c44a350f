#include "monitoring/peer_table.hpp"

#include <algorithm>

namespace odonata::monitoring {

std::vector<PeerEvent> PeerTable::OnHeartbeat(const Heartbeat& hb, Clock::time_point now) {
  if (peers_.size() >= kMaxPeers && peers_.count(hb.instance) == 0) {
    const auto oldest = std::min_element(
        peers_.begin(), peers_.end(),
        [](const auto& a, const auto& b) { return a.second.last_seen < b.second.last_seen; });
    peers_.erase(oldest);
  }
  std::vector<PeerEvent> events;
  Peer& p = peers_[hb.instance];
  PeerEvent e;
  e.instance = hb.instance;
  e.service = hb.service;
  e.state = hb.state;
  e.skipped = hb.skipped;
  e.repeated = hb.repeated;
  if (p.silent) {
    e.kind = PeerEvent::Kind::kBack;
    events.push_back(e);
  }
  if (hb.skipped > p.last.skipped || hb.repeated > p.last.repeated) {
    // A real-time plant falling behind: said once per heartbeat that shows new ones, so a loaded
    // machine's degradation is visible where the accuracy is watched.
    e.kind = PeerEvent::Kind::kFallingBehind;
    events.push_back(e);
  }
  p.last = hb;
  p.last_seen = now;
  p.silent = false;
  return events;
}

std::vector<PeerEvent> PeerTable::CheckSilence(Clock::time_point now, double timeout_s) {
  std::vector<PeerEvent> events;
  for (auto& [instance, p] : peers_) {
    const double silent_s = std::chrono::duration<double>(now - p.last_seen).count();
    if (!p.silent && p.last.state != "stopping" && silent_s > timeout_s) {
      PeerEvent e;
      e.kind = PeerEvent::Kind::kSilent;
      e.instance = instance;
      e.service = p.last.service;
      e.state = p.last.state;
      e.silent_s = silent_s;
      events.push_back(e);
      p.silent = true;
    }
  }
  return events;
}

nlohmann::json PeerTable::Summary() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [instance, p] : peers_) {
    const Heartbeat& h = p.last;
    j[instance] = {{"service", h.service},  {"state", h.state}, {"decode_errors", h.decode_errors},
                   {"dropped", h.dropped},  {"gaps", h.gaps},   {"skipped", h.skipped},
                   {"repeated", h.repeated}};
    if (!h.detail.empty()) j[instance]["detail"] = h.detail;
  }
  return j;
}

}  // namespace odonata::monitoring

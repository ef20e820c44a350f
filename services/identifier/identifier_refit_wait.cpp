#include <chrono>
#include <cstdio>

#include "identifier_node.hpp"

namespace odonata::identifier {

// While a landing waits for its refit the loop is blocked, and with it the heartbeat timer: say
// "refitting" first, so a lockstep generator waits instead of resending into a process that is
// not reading (docs/lcm.md §10), and keep beating meanwhile. Give up — the refit cancelled, the
// model kept — when a stop is asked for (SIGTERM is then obeyed within a training pass) or past
// kRefitWaitBoundS.
sysid::RefitWait IdentifierNode::WhileRefitting() {
  const auto now = std::chrono::steady_clock::now();
  const bool waiting = bus_.state() == "refitting";
  if (bus_.stop_requested() ||
      (waiting && now - refit_wait_began_ > std::chrono::seconds(kRefitWaitBoundS))) {
    std::fprintf(stderr, "%s: a refit was given up: %s\n", config_.instance.c_str(),
                 bus_.stop_requested() ? "a stop was asked for"
                                       : "it overran the wait's bound (kRefitWaitBoundS)");
    return sysid::RefitWait::kGiveUp;
  }
  if (waiting) {
    bus_.PublishHeartbeat();
    return sysid::RefitWait::kKeepWaiting;
  }
  refit_wait_began_ = now;
  state_before_refit_ = bus_.state();
  bus_.SetState("refitting");
  return sysid::RefitWait::kKeepWaiting;
}

}  // namespace odonata::identifier

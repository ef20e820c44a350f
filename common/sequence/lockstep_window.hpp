#pragma once
// The bounds of lockstep's window of commands in flight (docs/lcm.md §10), which the generator,
// the plant and every consumer must agree on: each holds more messages behind a missing one
// than the window can bring, and the plant keeps every answer a resend may ask for again.

#include <cstdint>

#include "sequence/sequence_window.hpp"

namespace odonata::pipeline {

/// The most commands a generator keeps in flight. A wider window could, after a run of losses,
/// bring a receiver a seq more than kConfirmLeap ahead, which it would hold back as a leap.
inline constexpr int64_t kMaxLockstepWindow = kConfirmLeap;

/// How far back a generator's resend may reach behind its newest command, and so how many
/// answers the plant keeps to publish again.
inline constexpr int64_t kLockstepResendReach = 64;

/// How long a lockstep sender (odonata-signal, odonata-replay) listens for identifier and logger
/// heartbeats before its first message, by default: two heartbeat periods (1 s) and a margin, so
/// one heartbeat lost or late (a lossy link, a busy machine) does not leave a consumer out of the
/// run. With one period, a run under 5 % loss and four CPU hogs once heard neither consumer.
inline constexpr double kLockstepDiscoverySeconds = 2.1;

}  // namespace odonata::pipeline

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

}  // namespace odonata::pipeline

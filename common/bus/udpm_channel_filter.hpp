#pragma once
// A classic BPF socket filter that lets the kernel drop LC02 datagrams on channels this process
// does not subscribe to, so a service is woken only for its own traffic: on one multicast group
// every process otherwise reads (and discards) every datagram of every other. docs/lcm.md §9.

#include <linux/filter.h>

#include <optional>
#include <string>
#include <vector>

namespace odonata::bus {

/// True when `subscription` names one channel literally (LCM reads subscriptions as regexes;
/// only literal names can be matched by the filter).
bool IsLiteralChannel(const std::string& subscription);

/// The filter program for a UDP socket whose subscriptions are exactly `channels`: an LC02
/// datagram passes when its channel is one of them; anything that is not LCM passes, to be
/// counted in user space. Fragments (LC03) pass when `fragments` (only the first names its
/// channel, so they are reassembled and judged in user space); without, every fragment is
/// dropped: no subscription takes a message that large. Empty when the program would not fit
/// cBPF's limits (too many or too long names): then nothing is filtered.
std::optional<std::vector<sock_filter>> ChannelFilterProgram(std::vector<std::string> channels,
                                                             bool fragments = true);

}  // namespace odonata::bus

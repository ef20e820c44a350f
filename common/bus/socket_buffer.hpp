#pragma once
// The receive buffer of a UDP socket that must ride out a burst while its process is off the CPU:
// the bus's own receiver (udpm_receiver) and odonata-mavlink's link.

namespace odonata::bus {

/// Without recv_buf_size in the URL: room for a lockstep window's burst (16 samples of commands,
/// states, beat states, receipts and predictions, plus a model snapshot's fragments) while the
/// process is off the CPU. The kernel's default (212992 bytes, in truesize) holds about 150 small
/// datagrams; a lost prediction is not resent (docs/lcm.md §5).
inline constexpr int kDefaultReceiveBuffer = 8 << 20;

/// Asks for `requested` bytes (<= 0: kDefaultReceiveBuffer). SO_RCVBUF is capped at
/// net.core.rmem_max (212992 on a stock Debian); a process with CAP_NET_ADMIN (the services run
/// as root in the tests and the systemd units) may exceed it. Best effort: never fails.
void SetReceiveBuffer(int fd, int requested);

}  // namespace odonata::bus

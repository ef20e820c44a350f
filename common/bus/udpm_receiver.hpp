#pragma once
// Receives LCM's udpm traffic on the service's own thread: a multicast socket joined like LCM's,
// read inside the Asio loop until it is empty. LCM 1.3.1 reads the socket in a thread of its own
// and wakes the service through a pipe, two wake-ups per datagram; the profile that led here is
// in docs/lcm.md §9. Sending is UdpmSender's.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/udp.hpp>
#include <lcm/lcm-cpp.hpp>

#include "bus/udpm_assembler.hpp"
#include "bus/udpm_endpoint.hpp"

namespace odonata::bus {

class UdpmReceiver {
 public:
  using Deliver = std::function<void(const lcm::ReceiveBuffer&, const std::string& channel)>;
  /// A datagram that was dropped: `malformed` (not LCM's format) or a message missing fragments.
  using Problem = std::function<void(bool malformed, const std::string& message)>;

  /// `n` datagrams the kernel dropped for this socket since the last call: its receive buffer
  /// was full (the process was off the CPU, or a flood), so they never reached it.
  using Overflow = std::function<void(int64_t n)>;

  /// Datagrams read per turn of the loop before timers get theirs.
  static constexpr int kBatch = 64;

  /// @throws std::runtime_error naming the group and port when the socket cannot join them.
  UdpmReceiver(
      boost::asio::io_context& io, const UdpmEndpoint& endpoint, Deliver deliver, Problem problem,
      Overflow overflow = [](int64_t) {});

  int64_t datagrams() const { return datagrams_; }
  /// Datagrams the kernel dropped for a full receive buffer, as far as the datagrams read since
  /// tell (the count comes with the next datagram read). Only on a socket that never had a
  /// channel filter (a recorder's): the kernel counts the filter's drops in the same counter.
  int64_t kernel_dropped() const { return kernel_dropped_; }
  /// Stops receiving (the loop's pending read is cancelled).
  void Close();
  /// Reads and delivers, now, the datagrams already queued on the socket, at most `most` of them
  /// (a flood must not hold a stop forever); returns how many were read. A stopping service
  /// handles what reached it before the stop instead of closing the socket on it.
  std::size_t DrainQueued(std::size_t most);
  /// Has the kernel drop LC02 datagrams on other channels than `channels` (udpm_channel_filter),
  /// and every LC03 fragment unless `fragments`; empty: receive everything. Returns false when the
  /// names cannot be filtered (then nothing is).
  bool Filter(const std::optional<std::vector<std::string>>& channels, bool fragments = true);

 private:
  enum class Read : std::uint8_t { kDatagram, kEmpty, kClosed };
  void Wait();
  void Drain();
  /// Reads one datagram, if one is queued, and delivers what it completes.
  Read ReadOne();

  boost::asio::ip::udp::socket socket_;
  Deliver deliver_;
  Problem problem_;
  Overflow overflow_;
  UdpmAssembler assembler_;
  std::vector<uint8_t> buffer_;
  int64_t datagrams_ = 0;
  uint32_t kernel_dropped_seen_ = 0;
  bool filtered_ = false;
  int64_t kernel_dropped_ = 0;
};

}  // namespace odonata::bus

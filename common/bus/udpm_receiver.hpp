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

  /// Datagrams read per turn of the loop before timers get theirs.
  static constexpr int kBatch = 64;

  /// @throws std::runtime_error naming the group and port when the socket cannot join them.
  UdpmReceiver(boost::asio::io_context& io, const UdpmEndpoint& endpoint, Deliver deliver,
               Problem problem);

  int64_t datagrams() const { return datagrams_; }
  /// Stops receiving (the loop's pending read is cancelled).
  void Close();
  /// Has the kernel drop LC02 datagrams on other channels than `channels` (udpm_channel_filter),
  /// and every LC03 fragment unless `fragments`; empty: receive everything. Returns false when the
  /// names cannot be filtered (then nothing is).
  bool Filter(const std::optional<std::vector<std::string>>& channels, bool fragments = true);

 private:
  void Wait();
  void Drain();

  boost::asio::ip::udp::socket socket_;
  Deliver deliver_;
  Problem problem_;
  UdpmAssembler assembler_;
  std::vector<uint8_t> buffer_;
  int64_t datagrams_ = 0;
};

}  // namespace odonata::bus

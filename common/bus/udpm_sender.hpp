#pragma once
// Sends LCM's udpm datagrams (LC02) itself, so several messages can leave in one system call: a
// receiver woken by the first would otherwise preempt the sender before the second (docs/lcm.md
// §9). Messages too large for one datagram are left to LCM, which fragments them.

#include <cstdint>
#include <string>
#include <vector>

#include "bus/udpm_endpoint.hpp"

namespace odonata::bus {

class UdpmSender {
 public:
  /// The largest channel + NUL + payload that fits one LC02 datagram (LCM's own limit).
  static constexpr std::size_t kMaxShortPayload = 65499;

  struct Message {
    const std::string* channel;
    const uint8_t* data;
    std::size_t size;
  };

  /// @throws std::runtime_error when the socket cannot be set up.
  explicit UdpmSender(const UdpmEndpoint& endpoint);
  ~UdpmSender();
  UdpmSender(const UdpmSender&) = delete;
  UdpmSender& operator=(const UdpmSender&) = delete;

  /// True when the message fits one datagram.
  static bool Fits(const std::string& channel, std::size_t size) {
    return channel.size() + 1 + size <= kMaxShortPayload;
  }
  /// Sends every message (each must Fit) in one sendmmsg; false when any was not sent.
  bool Send(const std::vector<Message>& messages);

 private:
  int fd_ = -1;
  uint32_t seqno_ = 0;
  std::vector<uint8_t> headers_;
  std::vector<uint8_t> group_address_;  // a sockaddr_in
};

}  // namespace odonata::bus

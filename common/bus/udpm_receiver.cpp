#include "bus/udpm_receiver.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/time.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include <boost/asio/ip/multicast.hpp>
#include <boost/asio/post.hpp>

#include "bus/socket_buffer.hpp"
#include "bus/udpm_channel_filter.hpp"

namespace odonata::bus {
namespace {

int64_t WallUtime() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

}  // namespace

UdpmReceiver::UdpmReceiver(boost::asio::io_context& io, const UdpmEndpoint& endpoint,
                           Deliver deliver, Problem problem, Overflow overflow)
    : socket_(io),
      deliver_(std::move(deliver)),
      problem_(std::move(problem)),
      overflow_(std::move(overflow)),
      buffer_(65536) {
  namespace ip = boost::asio::ip;
  const std::string where = endpoint.group + ":" + std::to_string(endpoint.port);
  try {
    const ip::address_v4 group = ip::make_address_v4(endpoint.group);
    socket_.open(ip::udp::v4());
    // Every process on the host binds the same group and port and gets its own copy.
    socket_.set_option(ip::udp::socket::reuse_address(true));
    SetReceiveBuffer(socket_.native_handle(), endpoint.recv_buf_size);
    const int on = 1;
    // The kernel's arrival time is the receive time LCM reports (and the logger records).
    if (setsockopt(socket_.native_handle(), SOL_SOCKET, SO_TIMESTAMP, &on, sizeof on) != 0)
      throw std::runtime_error("SO_TIMESTAMP refused");
    // The kernel's count of datagrams it dropped because the receive buffer was full, on every
    // datagram read: this process's own loss, which nothing else can see.
    setsockopt(socket_.native_handle(), SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on);
    socket_.bind(ip::udp::endpoint(group, endpoint.port));
    socket_.set_option(ip::multicast::join_group(group));
    socket_.non_blocking(true);
  } catch (const std::exception& e) {
    throw std::runtime_error(
        "cannot receive LCM multicast on " + where + ": " + e.what() +
        " (is there a multicast route? see docs/guide/live-system.md, 'Networking')");
  }
  Wait();
}

void UdpmReceiver::Wait() {
  socket_.async_wait(boost::asio::socket_base::wait_read,
                     [this](const boost::system::error_code& ec) {
                       if (!ec) Drain();
                     });
}

bool UdpmReceiver::Filter(const std::optional<std::vector<std::string>>& channels, bool fragments) {
  const int fd = socket_.native_handle();
  const auto program = channels ? ChannelFilterProgram(*channels, fragments) : std::nullopt;
  if (!program) {
    int unused = 0;
    setsockopt(fd, SOL_SOCKET, SO_DETACH_FILTER, &unused, sizeof unused);  // ENOENT if none
    return !channels;
  }
  sock_fprog fprog{static_cast<unsigned short>(program->size()),
                   const_cast<sock_filter*>(program->data())};
  filtered_ = true;
  return setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &fprog, sizeof fprog) == 0;
}

void UdpmReceiver::Close() {
  boost::system::error_code ignored;
  socket_.close(ignored);
}

void UdpmReceiver::Drain() {
  for (int i = 0; i < kBatch; ++i) {
    switch (ReadOne()) {
      case Read::kClosed:
        return;
      case Read::kEmpty:
        // Empty (or an error that is the kernel's business; the socket stays usable): wait for
        // the next datagram.
        Wait();
        return;
      case Read::kDatagram:
        break;
    }
  }
  // More may be waiting: read on after whatever else is ready (timers, signals).
  boost::asio::post(socket_.get_executor(), [this] { Drain(); });
}

std::size_t UdpmReceiver::DrainQueued(std::size_t most) {
  std::size_t read = 0;
  while (read < most && ReadOne() == Read::kDatagram) ++read;
  return read;
}

UdpmReceiver::Read UdpmReceiver::ReadOne() {
  while (true) {
    if (!socket_.is_open()) return Read::kClosed;
    sockaddr_storage from{};
    iovec iov{buffer_.data(), buffer_.size()};
    alignas(cmsghdr) char control[CMSG_SPACE(sizeof(timeval)) + CMSG_SPACE(sizeof(uint32_t))];
    msghdr msg{};
    msg.msg_name = &from;
    msg.msg_namelen = sizeof from;
    msg.msg_iov = &iov;
    msg.msg_iovlen = 1;
    msg.msg_control = control;
    msg.msg_controllen = sizeof control;
    const ssize_t n = recvmsg(socket_.native_handle(), &msg, MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      return Read::kEmpty;
    }
    ++datagrams_;
    if ((msg.msg_flags & MSG_TRUNC) != 0) {
      problem_(true, "a datagram larger than 64 kB (not LCM's format)");
      return Read::kDatagram;
    }
    int64_t utime = 0;
    for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
      if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SCM_TIMESTAMP) {
        timeval tv{};
        std::memcpy(&tv, CMSG_DATA(c), sizeof tv);
        utime = int64_t{tv.tv_sec} * 1000000 + tv.tv_usec;
      } else if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
        uint32_t dropped = 0;
        std::memcpy(&dropped, CMSG_DATA(c), sizeof dropped);
        // Cumulative for the socket (and wrapping at 2^32): what is new since the last count.
        const uint32_t fresh = dropped - kernel_dropped_seen_;
        kernel_dropped_seen_ = dropped;
        // The kernel counts the channel filter's drops there too: only a socket that never had
        // one (a recorder's) tells its overflows apart.
        if (!filtered_ && fresh > 0 && fresh < (1u << 31)) {
          kernel_dropped_ += fresh;
          overflow_(fresh);
        }
      }
    }
    if (utime == 0) utime = WallUtime();
    uint64_t sender = 0;
    if (from.ss_family == AF_INET) {
      const auto& in = reinterpret_cast<const sockaddr_in&>(from);
      sender = (uint64_t{ntohl(in.sin_addr.s_addr)} << 16) | ntohs(in.sin_port);
    }
    const UdpmAssembler::Result r =
        assembler_.Feed(sender, buffer_.data(), static_cast<std::size_t>(n));
    switch (r.verdict) {
      case UdpmAssembler::Verdict::kMessage: {
        lcm::ReceiveBuffer rbuf{};
        rbuf.data = const_cast<uint8_t*>(r.data);  // LCM's type is not const; no handler writes
        rbuf.data_size = r.size;
        rbuf.recv_utime = utime;
        deliver_(rbuf, std::string(r.channel));
        break;
      }
      case UdpmAssembler::Verdict::kHeld:
        break;
      case UdpmAssembler::Verdict::kMalformed:
        problem_(true, r.problem);
        break;
      case UdpmAssembler::Verdict::kIncomplete:
        problem_(false, r.problem);
        break;
    }
    return Read::kDatagram;
  }
}

}  // namespace odonata::bus

#include "bus/udpm_sender.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>

#include "bus/udpm_assembler.hpp"

namespace odonata::bus {

UdpmSender::UdpmSender(const UdpmEndpoint& endpoint) : group_address_(sizeof(sockaddr_in)) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_port = htons(endpoint.port);
  if (inet_aton(endpoint.group.c_str(), &to.sin_addr) == 0)
    throw std::runtime_error("bad multicast group " + endpoint.group);
  std::memcpy(group_address_.data(), &to, sizeof to);
  fd_ = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  const unsigned int ttl = static_cast<unsigned int>(endpoint.ttl);
  const unsigned int loop = 1;  // processes on this host are on the bus too
  if (fd_ < 0 || setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, sizeof ttl) != 0 ||
      setsockopt(fd_, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, sizeof loop) != 0) {
    const std::string why = std::strerror(errno);
    if (fd_ >= 0) close(fd_);
    throw std::runtime_error("cannot open a udpm send socket: " + why);
  }
}

UdpmSender::~UdpmSender() {
  if (fd_ >= 0) close(fd_);
}

bool UdpmSender::Send(const std::vector<Message>& messages) {
  const std::size_t n = messages.size();
  constexpr std::size_t kHeader = 8;
  headers_.assign(n * kHeader, 0);
  std::vector<iovec> iov(3 * n);
  std::vector<mmsghdr> msgs(n);
  for (std::size_t i = 0; i < n; ++i) {
    const Message& m = messages[i];
    uint8_t* h = headers_.data() + i * kHeader;
    const uint32_t magic = htonl(UdpmAssembler::kMagicShort), seqno = htonl(seqno_++);
    std::memcpy(h, &magic, 4);
    std::memcpy(h + 4, &seqno, 4);
    iov[3 * i] = {h, kHeader};
    // The channel with its NUL, straight from the std::string.
    iov[3 * i + 1] = {const_cast<char*>(m.channel->c_str()), m.channel->size() + 1};
    iov[3 * i + 2] = {const_cast<uint8_t*>(m.data), m.size};
    msgs[i] = {};
    msgs[i].msg_hdr.msg_name = group_address_.data();
    msgs[i].msg_hdr.msg_namelen = static_cast<socklen_t>(group_address_.size());
    msgs[i].msg_hdr.msg_iov = &iov[3 * i];
    msgs[i].msg_hdr.msg_iovlen = 3;
  }
  std::size_t sent = 0;
  while (sent < n) {
    const int r = sendmmsg(fd_, msgs.data() + sent, static_cast<unsigned int>(n - sent), 0);
    if (r < 0) {
      if (errno == EINTR) continue;
      return false;
    }
    sent += static_cast<std::size_t>(r);
  }
  return true;
}

}  // namespace odonata::bus

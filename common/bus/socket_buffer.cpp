#include "bus/socket_buffer.hpp"

#include <sys/socket.h>

namespace odonata::bus {

void SetReceiveBuffer(int fd, int requested) {
  const int want = requested > 0 ? requested : kDefaultReceiveBuffer;
  setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &want, sizeof want);
  int got = 0;
  socklen_t len = sizeof got;
  getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &got, &len);
  if (got / 2 < want) setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want);  // may fail
}

}  // namespace odonata::bus

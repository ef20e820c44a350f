#include "io/atomic_file.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace odonata::io {
namespace {
std::string Errno() { return std::strerror(errno); }
}  // namespace

void WriteFileAtomically(const std::string& path, const std::string& content) {
  std::vector<char> tmp(path.begin(), path.end());
  for (const char c : std::string(".tmp.XXXXXX")) tmp.push_back(c);
  tmp.push_back('\0');
  const int fd = mkostemp(tmp.data(), O_CLOEXEC);
  if (fd < 0) throw std::runtime_error(path + ": cannot create a temporary file (" + Errno() + ")");
  const auto fail = [&](const std::string& what) {
    const std::string why = Errno();
    ::close(fd);
    ::unlink(tmp.data());
    throw std::runtime_error(path + ": " + what + " (" + why + ")");
  };
  std::size_t done = 0;
  while (done < content.size()) {
    const ssize_t n = ::write(fd, content.data() + done, content.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) fail("write failed");
    done += static_cast<std::size_t>(n);
  }
  // mkstemp's 0600 would make a model file unreadable to the operator's other tools.
  if (::fchmod(fd, 0644) != 0) fail("cannot set permissions");
  if (::fsync(fd) != 0) fail("cannot flush to disk");
  if (::close(fd) != 0) {
    const std::string why = Errno();
    ::unlink(tmp.data());
    throw std::runtime_error(path + ": close failed (" + why + ")");
  }
  if (std::rename(tmp.data(), path.c_str()) != 0) {
    const std::string why = Errno();
    ::unlink(tmp.data());
    throw std::runtime_error(path + ": cannot rename the temporary file over it (" + why + ")");
  }
}

std::string ConfinedPath(const std::string& directory, const std::string& name) {
  if (directory.empty())
    throw std::invalid_argument("no directory is configured for files named over the bus");
  if (name.empty()) throw std::invalid_argument("empty file name");
  if (name.size() > 128) throw std::invalid_argument("file name longer than 128 characters");
  if (name.front() == '.')
    throw std::invalid_argument("file name '" + name + "' starts with '.' (hidden or '..')");
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '.' || c == '_' || c == '-';
    if (!ok) {
      throw std::invalid_argument("file name '" + name +
                                  "' is not a plain name (only letters, digits, '.', '_', '-'; "
                                  "no directories)");
    }
  }
  return directory.back() == '/' ? directory + name : directory + "/" + name;
}

}  // namespace odonata::io

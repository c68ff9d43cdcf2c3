// The simulator's TCP listener (lmcfg sim --tcp): POSIX sockets.
#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include "sim/server.hpp"

namespace lmcfg::sim {

Result<transport::UniqueFd> listen_tcp(const std::string& host, std::uint16_t port,
                                       std::uint16_t& bound_port) {
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1)
    return Error(Errc::invalid_argument, "listen address '" + host + "' is not an IPv4 address");
  transport::UniqueFd fd(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!fd) return Error(Errc::io_error, std::string("socket: ") + std::strerror(errno));
  int one = 1;
  ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (::bind(fd.get(), reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    return Error(Errc::io_error,
                 "bind " + host + ":" + std::to_string(port) + ": " + std::strerror(errno));
  if (::listen(fd.get(), 4) != 0)
    return Error(Errc::io_error, std::string("listen: ") + std::strerror(errno));
  socklen_t len = sizeof addr;
  if (::getsockname(fd.get(), reinterpret_cast<sockaddr*>(&addr), &len) != 0)
    return Error(Errc::io_error, std::string("getsockname: ") + std::strerror(errno));
  bound_port = ntohs(addr.sin_port);
  return fd;
}

Result<transport::UniqueFd> accept_client(int listen_fd, transport::Millis timeout) {
  pollfd p{listen_fd, POLLIN, 0};
  const int rc = ::poll(&p, 1, static_cast<int>(timeout.count()));
  if (rc < 0 && errno != EINTR)
    return Error(Errc::io_error, std::string("poll: ") + std::strerror(errno));
  if (rc <= 0) return transport::UniqueFd();
  transport::UniqueFd c(::accept4(listen_fd, nullptr, nullptr, SOCK_CLOEXEC));
  if (!c && errno != EINTR && errno != EAGAIN)
    return Error(Errc::io_error, std::string("accept: ") + std::strerror(errno));
  return c;
}

}  // namespace lmcfg::sim

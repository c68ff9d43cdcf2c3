// TCP client for serial-to-Ethernet gateways: non-blocking connect with a deadline.
#include <errno.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"

namespace lmcfg::transport {

namespace {

// Connects one resolved address; 0 on success, otherwise the errno (ETIMEDOUT at the deadline).
int connect_one(const addrinfo& ai, Clock::time_point deadline, UniqueFd& out) {
  UniqueFd fd(
      ::socket(ai.ai_family, ai.ai_socktype | SOCK_NONBLOCK | SOCK_CLOEXEC, ai.ai_protocol));
  if (!fd) return errno;
  if (::connect(fd.get(), ai.ai_addr, ai.ai_addrlen) != 0) {
    if (errno != EINPROGRESS && errno != EINTR) return errno;
    for (;;) {
      pollfd pfd{fd.get(), POLLOUT, 0};
      const int r = ::poll(&pfd, 1, detail::ms_left(deadline));
      if (r < 0 && errno == EINTR) continue;
      if (r < 0) return errno;
      if (r == 0) {
        if (Clock::now() >= deadline) return ETIMEDOUT;
        continue;
      }
      break;
    }
    int soerr = 0;
    socklen_t len = sizeof soerr;
    if (::getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &soerr, &len) != 0) return errno;
    if (soerr != 0) return soerr;
  }
  const int one = 1;
  ::setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  ::setsockopt(fd.get(), SOL_SOCKET, SO_KEEPALIVE, &one, sizeof one);
  out = std::move(fd);
  return 0;
}

}  // namespace

Result<TcpConnection> connect_tcp(const std::string& host, std::uint16_t port,
                                  Millis connect_timeout, const std::string& scheme) {
  LMCFG_ASSIGN_OR_RETURN(auto target, detail::tcp_target(host, port, scheme));
  const std::string& name = target.name;
  const std::string& where = target.where;

  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_NUMERICSERV | AI_ADDRCONFIG;
  addrinfo* res = nullptr;
  const std::string service = std::to_string(port);
  int rc = ::getaddrinfo(name.c_str(), service.c_str(), &hints, &res);
  if (rc == EAI_NONAME || rc == EAI_ADDRFAMILY) {
    // AI_ADDRCONFIG hides loopback-only families on hosts without other addresses.
    hints.ai_flags = AI_NUMERICSERV;
    rc = ::getaddrinfo(name.c_str(), service.c_str(), &hints, &res);
  }
  if (rc != 0) {
    const std::string why = rc == EAI_SYSTEM ? std::strerror(errno) : ::gai_strerror(rc);
    return Error(Errc::not_found, scheme + " " + where + ": cannot resolve host: " + why);
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> list(res, &::freeaddrinfo);

  const auto deadline = Clock::now() + std::max(connect_timeout, Millis(0));
  int last = ECONNREFUSED;
  for (const addrinfo* ai = list.get(); ai != nullptr; ai = ai->ai_next) {
    UniqueFd fd;
    last = connect_one(*ai, deadline, fd);
    if (last == 0) return TcpConnection{std::move(fd), where};
    if (last == ETIMEDOUT) break;
  }
  if (last == ETIMEDOUT) {
    return Error(Errc::timeout, scheme + " " + where + ": connect timed out after " +
                                    std::to_string(connect_timeout.count()) + " ms");
  }
  return Error(Errc::io_error, scheme + " " + where + ": cannot connect: " + std::strerror(last));
}

}  // namespace lmcfg::transport

#include "web/web_socket.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace lmcfg::web {

namespace {

void set_nonblocking(int fd) { ::fcntl(fd, F_SETFL, ::fcntl(fd, F_GETFL, 0) | O_NONBLOCK); }

std::string address_text(const sockaddr_storage& sa) {
  char buf[INET6_ADDRSTRLEN] = "";
  if (sa.ss_family == AF_INET) {
    ::inet_ntop(AF_INET, &reinterpret_cast<const sockaddr_in&>(sa).sin_addr, buf, sizeof buf);
  } else if (sa.ss_family == AF_INET6) {
    const auto& a6 = reinterpret_cast<const sockaddr_in6&>(sa).sin6_addr;
    if (IN6_IS_ADDR_V4MAPPED(&a6)) {
      ::inet_ntop(AF_INET, &a6.s6_addr[12], buf, sizeof buf);
    } else {
      ::inet_ntop(AF_INET6, &a6, buf, sizeof buf);
    }
  }
  return buf;
}

}  // namespace

Result<Listener> listen_on(const std::string& host, int port) {
  const Error cannot(Errc::io_error, "cannot listen on " + host + ":" + std::to_string(port) +
                                         " (address in use or not on this host)");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* res = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res) != 0 || !res)
    return cannot;
  int fd = -1;
  for (addrinfo* a = res; a && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    // SO_REUSEADDR only: with SO_REUSEPORT a second lmcfg serve would bind
    // the same port and the kernel would share the connections between them.
    int yes = 1;
    ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
    if (::bind(fd, a->ai_addr, a->ai_addrlen) != 0 || ::listen(fd, 256) != 0) {
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(res);
  if (fd < 0) return cannot;
  sockaddr_storage sa{};
  socklen_t len = sizeof sa;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&sa), &len);
  Listener l;
  l.socket = fd;
  l.port = ntohs(sa.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6&>(sa).sin6_port
                                          : reinterpret_cast<sockaddr_in&>(sa).sin_port);
  set_nonblocking(fd);
  return l;
}

int accept_one(int listener, std::string& peer) {
  sockaddr_storage sa{};
  socklen_t len = sizeof sa;
  const int fd = ::accept4(listener, reinterpret_cast<sockaddr*>(&sa), &len, SOCK_CLOEXEC);
  if (fd < 0) return -1;  // EAGAIN, or a resource limit: the next wait tries again
  set_nonblocking(fd);
  int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
  peer = address_text(sa);
  return fd;
}

IoStep recv_some(int socket, char* buf, std::size_t size) {
  IoStep r;
  const ssize_t n = ::recv(socket, buf, size, 0);
  if (n > 0) {
    r.n = static_cast<std::size_t>(n);
  } else if (n == 0) {
    r.closed = true;
  } else if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
    r.want_read = true;
  } else {
    r.closed = true;
    r.error = std::strerror(errno);
  }
  return r;
}

IoStep send_some(int socket, const char* buf, std::size_t size) {
  IoStep r;
  const ssize_t n = ::send(socket, buf, size, MSG_NOSIGNAL);
  if (n >= 0) {
    r.n = static_cast<std::size_t>(n);
    if (n == 0) r.want_write = true;
  } else if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
    r.want_write = true;
  } else {
    r.closed = true;
    r.error = std::strerror(errno);
  }
  return r;
}

void send_now(int socket, const std::string& bytes) {
  [[maybe_unused]] auto n = ::send(socket, bytes.data(), bytes.size(), MSG_NOSIGNAL | MSG_DONTWAIT);
}

void close_socket(int socket) {
  if (socket >= 0) ::close(socket);
}

bool is_loopback_address(const std::string& host) {
  in_addr v4{};
  if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  return ::inet_pton(AF_INET6, host.c_str(), &v6) == 1 && IN6_IS_ADDR_LOOPBACK(&v6);
}

// TLS writes go through OpenSSL's socket BIO, which cannot pass MSG_NOSIGNAL.
void ignore_broken_pipe() { ::signal(SIGPIPE, SIG_IGN); }

Waker::~Waker() {
  close_socket(rx_);
  close_socket(tx_);
}

Result<void> Waker::open() {
  int fds[2];
  if (::pipe2(fds, O_NONBLOCK | O_CLOEXEC) != 0)
    return Error(Errc::io_error, "cannot create the server's wake-up pipe");
  rx_ = fds[0];
  tx_ = fds[1];
  return {};
}

void Waker::poke() const {
  const char c = 1;
  [[maybe_unused]] auto n = ::write(tx_, &c, 1);
}

void Waker::drain() const {
  char drain[256];
  while (::read(rx_, drain, sizeof drain) > 0) {
  }
}

bool wait_sockets(std::vector<Watch>& watches, int timeout_ms) {
  std::vector<pollfd> fds;
  fds.reserve(watches.size());
  for (const Watch& w : watches)
    fds.push_back(
        {w.socket, static_cast<short>((w.read ? POLLIN : 0) | (w.write ? POLLOUT : 0)), 0});
  const int n = ::poll(fds.data(), fds.size(), timeout_ms);
  const bool ok = n >= 0 || errno == EINTR;
  for (std::size_t i = 0; i < fds.size(); ++i) {
    const short re = fds[i].revents;
    watches[i].readable = re & POLLIN;
    watches[i].writable = re & POLLOUT;
    watches[i].hangup = re & POLLHUP;
    watches[i].failed = re & (POLLERR | POLLNVAL);
  }
  return ok;
}

}  // namespace lmcfg::web

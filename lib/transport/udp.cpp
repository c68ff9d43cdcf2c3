// UDP datagram transport and server socket (POSIX). See udp.hpp.
#include "transport/udp.hpp"

#include <arpa/inet.h>
#include <errno.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstring>

#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"

namespace lmcfg::transport {

namespace {

constexpr std::size_t kMaxDatagram = 1500;

Error udp_errno(const std::string& what, int err) {
  return Error(Errc::io_error, what + ": " + std::strerror(err));
}

Result<sockaddr_in> resolve_ipv4(const std::string& host, std::uint16_t port) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* res = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &res);
  if (rc != 0 || !res) {
    return Error(Errc::invalid_argument, "udp " + host + ":" + std::to_string(port) +
                                             ": cannot resolve '" + host +
                                             "' to an IPv4 address (" + ::gai_strerror(rc) + ")");
  }
  sockaddr_in a{};
  std::memcpy(&a, res->ai_addr, sizeof a);
  ::freeaddrinfo(res);
  a.sin_port = htons(port);
  return a;
}

std::string addr_text(const sockaddr_in& a) {
  char buf[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &a.sin_addr, buf, sizeof buf);
  return std::string(buf) + ":" + std::to_string(ntohs(a.sin_port));
}

// Waits for the socket to be readable; false at the deadline.
Result<bool> wait_readable(int fd, Clock::time_point deadline) {
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    const int r = ::poll(&p, 1, detail::ms_left(deadline));
    if (r < 0 && errno == EINTR) continue;
    if (r < 0) return udp_errno("udp poll", errno);
    return r > 0;
  }
}

class UdpTransport final : public Transport {
 public:
  UdpTransport(UniqueFd fd, std::string where) : fd_(std::move(fd)), where_(std::move(where)) {}

  Result<void> write(ByteView bytes) override {
    const ssize_t n = ::send(fd_.get(), bytes.data(), bytes.size(), 0);
    // A refused earlier datagram (ICMP port unreachable) surfaces here as
    // ECONNREFUSED: the peer may still come; the answer wait says "no answer".
    if (n < 0 && errno != ECONNREFUSED) return udp_errno("udp send to " + where_, errno);
    return {};
  }

  Result<Bytes> read_some(Millis timeout) override {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
      LMCFG_ASSIGN_OR_RETURN(bool ready, wait_readable(fd_.get(), deadline));
      if (!ready) return Bytes{};
      Bytes buf(kMaxDatagram);
      const ssize_t n = ::recv(fd_.get(), buf.data(), buf.size(), 0);
      if (n >= 0) {
        buf.resize(static_cast<std::size_t>(n));
        return buf;
      }
      if (errno == EINTR || errno == EAGAIN || errno == ECONNREFUSED) continue;
      return udp_errno("udp receive from " + where_, errno);
    }
  }

  void discard_input() override {
    Bytes buf(kMaxDatagram);
    while (::recv(fd_.get(), buf.data(), buf.size(), MSG_DONTWAIT) >= 0 || errno == ECONNREFUSED) {
    }
  }

  std::string describe() const override { return "udp " + where_; }

 private:
  UniqueFd fd_;
  std::string where_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_udp(const std::string& host, std::uint16_t port,
                                            const UdpOptions& opt) {
  LMCFG_ASSIGN_OR_RETURN(auto peer, resolve_ipv4(host, port));
  UniqueFd fd(::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0));
  if (!fd) return udp_errno("udp socket", errno);
  const int one = 1;
  ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  ::setsockopt(fd.get(), SOL_SOCKET, SO_REUSEPORT, &one, sizeof one);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_addr.s_addr = htonl(INADDR_ANY);
  local.sin_port = htons(opt.local_port);
  if (::bind(fd.get(), reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    return udp_errno("udp: cannot bind the local port " + std::to_string(opt.local_port) +
                         " (LinUDP master port) for " + addr_text(peer),
                     errno);
  }
  if (::connect(fd.get(), reinterpret_cast<const sockaddr*>(&peer), sizeof peer) != 0)
    return udp_errno("udp connect to " + addr_text(peer), errno);
  return std::unique_ptr<Transport>(std::make_unique<UdpTransport>(std::move(fd), addr_text(peer)));
}

Result<UdpServer> UdpServer::bind(const std::string& host, std::uint16_t port) {
  LMCFG_ASSIGN_OR_RETURN(auto addr, resolve_ipv4(host, port));
  const int fd = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return udp_errno("udp socket", errno);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    return udp_errno("udp: cannot bind " + addr_text(addr), err);
  }
  sockaddr_in bound{};
  socklen_t len = sizeof bound;
  ::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &len);
  return UdpServer(fd, ntohs(bound.sin_port));
}

UdpServer::UdpServer(UdpServer&& o) noexcept : fd_(o.fd_), port_(o.port_) { o.fd_ = -1; }
UdpServer& UdpServer::operator=(UdpServer&& o) noexcept {
  if (this != &o) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = o.fd_;
    port_ = o.port_;
    o.fd_ = -1;
  }
  return *this;
}
UdpServer::~UdpServer() {
  if (fd_ >= 0) ::close(fd_);
}

Result<std::optional<UdpServer::Datagram>> UdpServer::receive(Millis timeout) {
  LMCFG_ASSIGN_OR_RETURN(bool ready, wait_readable(fd_, Clock::now() + timeout));
  if (!ready) return std::optional<Datagram>{};
  Datagram d;
  d.bytes.resize(kMaxDatagram);
  sockaddr_in from{};
  socklen_t len = sizeof from;
  const ssize_t n =
      ::recvfrom(fd_, d.bytes.data(), d.bytes.size(), 0, reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) {
    if (errno == EINTR || errno == EAGAIN) return std::optional<Datagram>{};
    return udp_errno("udp receive", errno);
  }
  d.bytes.resize(static_cast<std::size_t>(n));
  d.from = addr_text(from);
  d.from_ip = ntohl(from.sin_addr.s_addr);
  d.from_port = ntohs(from.sin_port);
  return std::optional<Datagram>(std::move(d));
}

Result<void> UdpServer::send_to(const Datagram& peer, ByteView bytes) {
  sockaddr_in to{};
  to.sin_family = AF_INET;
  to.sin_addr.s_addr = htonl(peer.from_ip);
  to.sin_port = htons(peer.from_port);
  if (::sendto(fd_, bytes.data(), bytes.size(), 0, reinterpret_cast<const sockaddr*>(&to),
               sizeof to) < 0)
    return udp_errno("udp send to " + peer.from, errno);
  return {};
}

}  // namespace lmcfg::transport

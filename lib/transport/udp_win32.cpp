// Windows: udp.cpp's datagram transport and server socket on Winsock. See udp.hpp.
// Differences from Linux, each for the same behaviour:
//  - SO_REUSEADDR alone shares the LinUDP master port 41136 (Windows has no
//    SO_REUSEPORT; its SO_REUSEADDR lets several sockets bind one port).
//  - An ICMP "port unreachable" after a datagram makes Windows report
//    WSAECONNRESET on the next receive (Linux: ECONNREFUSED); SIO_UDP_CONNRESET
//    turns that off where it exists, and both errors are skipped as on Linux.
#include <mswsock.h>

#include <cstring>

#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"
#include "transport/udp.hpp"
#include "transport/winsock_win32.hpp"

#ifndef SIO_UDP_CONNRESET
#define SIO_UDP_CONNRESET _WSAIOW(IOC_VENDOR, 12)
#endif

namespace lmcfg::transport {

namespace {

constexpr std::size_t kMaxDatagram = 1500;

Error udp_error(const std::string& what, int err) {
  return Error(Errc::io_error, what + ": " + win32::wsa_text(err));
}

bool is_icmp_echo(int err) { return err == WSAECONNRESET || err == WSAECONNREFUSED; }

Result<sockaddr_in> resolve_ipv4(const std::string& host, std::uint16_t port) {
  LMCFG_TRY(win32::winsock_ready());
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo* res = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &res);
  if (rc != 0 || !res) {
    return Error(Errc::invalid_argument, "udp " + host + ":" + std::to_string(port) +
                                             ": cannot resolve '" + host +
                                             "' to an IPv4 address (" + win32::wsa_text(rc) + ")");
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

Result<UniqueFd> udp_socket() {
  const SOCKET s =
      ::WSASocketW(AF_INET, SOCK_DGRAM, IPPROTO_UDP, nullptr, 0, WSA_FLAG_NO_HANDLE_INHERIT);
  if (s == INVALID_SOCKET) return udp_error("udp socket", ::WSAGetLastError());
  BOOL report = FALSE;
  DWORD returned = 0;
  ::WSAIoctl(s, SIO_UDP_CONNRESET, &report, sizeof report, nullptr, 0, &returned, nullptr, nullptr);
  return UniqueFd(win32::from_socket(s));
}

// Waits for the socket to be readable; false at the deadline.
Result<bool> wait_readable(SOCKET s, Clock::time_point deadline) {
  const int r = win32::wait_socket(s, false, detail::ms_left(deadline));
  if (r == SOCKET_ERROR) return udp_error("udp select", ::WSAGetLastError());
  return r > 0;
}

class UdpTransport final : public Transport {
 public:
  UdpTransport(UniqueFd fd, std::string where) : fd_(std::move(fd)), where_(std::move(where)) {}

  Result<void> write(ByteView bytes) override {
    const int n = ::send(sock(), reinterpret_cast<const char*>(bytes.data()),
                         static_cast<int>(bytes.size()), 0);
    // A refused earlier datagram: the peer may still come; the answer wait says "no answer".
    if (n < 0 && !is_icmp_echo(::WSAGetLastError()))
      return udp_error("udp send to " + where_, ::WSAGetLastError());
    return {};
  }

  Result<Bytes> read_some(Millis timeout) override {
    const auto deadline = Clock::now() + timeout;
    for (;;) {
      LMCFG_ASSIGN_OR_RETURN(bool ready, wait_readable(sock(), deadline));
      if (!ready) return Bytes{};
      Bytes buf(kMaxDatagram);
      const int n =
          ::recv(sock(), reinterpret_cast<char*>(buf.data()), static_cast<int>(buf.size()), 0);
      if (n >= 0) {
        buf.resize(static_cast<std::size_t>(n));
        return buf;
      }
      const int err = ::WSAGetLastError();
      if (err == WSAEINTR || err == WSAEWOULDBLOCK || is_icmp_echo(err)) continue;
      return udp_error("udp receive from " + where_, err);
    }
  }

  void discard_input() override {
    Bytes buf(kMaxDatagram);
    for (int i = 0; i < 4096; ++i) {
      if (win32::wait_socket(sock(), false, 0) <= 0) break;
      if (::recv(sock(), reinterpret_cast<char*>(buf.data()), static_cast<int>(buf.size()), 0) <
              0 &&
          !is_icmp_echo(::WSAGetLastError()))
        break;
    }
  }

  std::string describe() const override { return "udp " + where_; }

 private:
  SOCKET sock() const { return win32::to_socket(fd_.get()); }
  UniqueFd fd_;
  std::string where_;
};

}  // namespace

Result<std::unique_ptr<Transport>> open_udp(const std::string& host, std::uint16_t port,
                                            const UdpOptions& opt) {
  LMCFG_ASSIGN_OR_RETURN(auto peer, resolve_ipv4(host, port));
  LMCFG_ASSIGN_OR_RETURN(UniqueFd fd, udp_socket());
  const SOCKET s = win32::to_socket(fd.get());
  const BOOL one = TRUE;
  ::setsockopt(s, SOL_SOCKET, SO_REUSEADDR, reinterpret_cast<const char*>(&one), sizeof one);
  sockaddr_in local{};
  local.sin_family = AF_INET;
  local.sin_addr.s_addr = htonl(INADDR_ANY);
  local.sin_port = htons(opt.local_port);
  if (::bind(s, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
    return udp_error("udp: cannot bind the local port " + std::to_string(opt.local_port) +
                         " (LinUDP master port) for " + addr_text(peer),
                     ::WSAGetLastError());
  }
  if (::connect(s, reinterpret_cast<const sockaddr*>(&peer), sizeof peer) != 0)
    return udp_error("udp connect to " + addr_text(peer), ::WSAGetLastError());
  return std::unique_ptr<Transport>(std::make_unique<UdpTransport>(std::move(fd), addr_text(peer)));
}

Result<UdpServer> UdpServer::bind(const std::string& host, std::uint16_t port) {
  LMCFG_ASSIGN_OR_RETURN(auto addr, resolve_ipv4(host, port));
  LMCFG_ASSIGN_OR_RETURN(UniqueFd fd, udp_socket());
  const SOCKET s = win32::to_socket(fd.get());
  if (::bind(s, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0)
    return udp_error("udp: cannot bind " + addr_text(addr), ::WSAGetLastError());
  sockaddr_in bound{};
  int len = sizeof bound;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&bound), &len);
  return UdpServer(fd.release(), ntohs(bound.sin_port));
}

UdpServer::UdpServer(UdpServer&& o) noexcept : fd_(o.fd_), port_(o.port_) { o.fd_ = -1; }
UdpServer& UdpServer::operator=(UdpServer&& o) noexcept {
  if (this != &o) {
    UniqueFd old(fd_);  // closes ours
    fd_ = o.fd_;
    port_ = o.port_;
    o.fd_ = -1;
  }
  return *this;
}
UdpServer::~UdpServer() { UniqueFd closing(fd_); }

Result<std::optional<UdpServer::Datagram>> UdpServer::receive(Millis timeout) {
  const SOCKET s = win32::to_socket(fd_);
  LMCFG_ASSIGN_OR_RETURN(bool ready, wait_readable(s, Clock::now() + timeout));
  if (!ready) return std::optional<Datagram>{};
  Datagram d;
  d.bytes.resize(kMaxDatagram);
  sockaddr_in from{};
  int len = sizeof from;
  const int n =
      ::recvfrom(s, reinterpret_cast<char*>(d.bytes.data()), static_cast<int>(d.bytes.size()), 0,
                 reinterpret_cast<sockaddr*>(&from), &len);
  if (n < 0) {
    const int err = ::WSAGetLastError();
    if (err == WSAEINTR || err == WSAEWOULDBLOCK || is_icmp_echo(err))
      return std::optional<Datagram>{};
    return udp_error("udp receive", err);
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
  if (::sendto(win32::to_socket(fd_), reinterpret_cast<const char*>(bytes.data()),
               static_cast<int>(bytes.size()), 0, reinterpret_cast<const sockaddr*>(&to),
               sizeof to) < 0)
    return udp_error("udp send to " + peer.from, ::WSAGetLastError());
  return {};
}

}  // namespace lmcfg::transport

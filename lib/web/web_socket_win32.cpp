// Windows: Winsock 2.2. WSAPoll is the wait: transport/winsock_win32.hpp's
// reason for select() (WSAPoll not reporting a failed connect before Windows
// 10 2004) concerns connecting sockets, which a server never has.
#include "transport/winsock_win32.hpp"
#include "web/web_socket.hpp"

namespace lmcfg::web {

namespace w32 = lmcfg::transport::win32;

namespace {

void set_nonblocking(SOCKET s) {
  u_long on = 1;
  ::ioctlsocket(s, FIONBIO, &on);
}

std::string address_text(const sockaddr_storage& sa) {
  char buf[INET6_ADDRSTRLEN] = "";
  if (sa.ss_family == AF_INET) {
    auto a = reinterpret_cast<const sockaddr_in&>(sa).sin_addr;
    ::inet_ntop(AF_INET, &a, buf, sizeof buf);
  } else if (sa.ss_family == AF_INET6) {
    auto a6 = reinterpret_cast<const sockaddr_in6&>(sa).sin6_addr;
    if (IN6_IS_ADDR_V4MAPPED(&a6)) {
      ::inet_ntop(AF_INET, &a6.s6_addr[12], buf, sizeof buf);
    } else {
      ::inet_ntop(AF_INET6, &a6, buf, sizeof buf);
    }
  }
  return buf;
}

IoStep failed_step(int err) {
  IoStep r;
  r.closed = true;
  r.error = w32::wsa_text(err);
  return r;
}

int port_of(SOCKET s) {
  sockaddr_storage sa{};
  int len = sizeof sa;
  ::getsockname(s, reinterpret_cast<sockaddr*>(&sa), &len);
  return ntohs(sa.ss_family == AF_INET6 ? reinterpret_cast<sockaddr_in6&>(sa).sin6_port
                                        : reinterpret_cast<sockaddr_in&>(sa).sin_port);
}

}  // namespace

Result<Listener> listen_on(const std::string& host, int port) {
  LMCFG_TRY(w32::winsock_ready());
  const Error cannot(Errc::io_error, "cannot listen on " + host + ":" + std::to_string(port) +
                                         " (address in use or not on this host)");
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* res = nullptr;
  if (::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &res) != 0 || !res)
    return cannot;
  SOCKET s = INVALID_SOCKET;
  for (addrinfo* a = res; a && s == INVALID_SOCKET; a = a->ai_next) {
    // Not inherited: a notify command started by the service must not hold
    // the port after the service ends.
    s = ::WSASocketW(a->ai_family, a->ai_socktype, a->ai_protocol, nullptr, 0,
                     WSA_FLAG_NO_HANDLE_INHERIT);
    if (s == INVALID_SOCKET) continue;
    // SO_EXCLUSIVEADDRUSE: on Windows SO_REUSEADDR would let a second
    // lmcfg serve bind the same port and take connections from the first.
    int one = 1;
    ::setsockopt(s, SOL_SOCKET, SO_EXCLUSIVEADDRUSE, reinterpret_cast<const char*>(&one),
                 sizeof one);
    if (::bind(s, a->ai_addr, static_cast<int>(a->ai_addrlen)) != 0 || ::listen(s, 256) != 0) {
      ::closesocket(s);
      s = INVALID_SOCKET;
    }
  }
  ::freeaddrinfo(res);
  if (s == INVALID_SOCKET) return cannot;
  set_nonblocking(s);
  Listener l;
  l.socket = w32::from_socket(s);
  l.port = port_of(s);
  return l;
}

int accept_one(int listener, std::string& peer) {
  sockaddr_storage sa{};
  int len = sizeof sa;
  const SOCKET s = ::accept(w32::to_socket(listener), reinterpret_cast<sockaddr*>(&sa), &len);
  if (s == INVALID_SOCKET) return -1;  // WSAEWOULDBLOCK, or a resource limit
  ::SetHandleInformation(reinterpret_cast<HANDLE>(s), HANDLE_FLAG_INHERIT, 0);
  set_nonblocking(s);
  int one = 1;
  ::setsockopt(s, IPPROTO_TCP, TCP_NODELAY, reinterpret_cast<const char*>(&one), sizeof one);
  peer = address_text(sa);
  return w32::from_socket(s);
}

IoStep recv_some(int socket, char* buf, std::size_t size) {
  IoStep r;
  const int n = ::recv(w32::to_socket(socket), buf, static_cast<int>(size), 0);
  if (n > 0) {
    r.n = static_cast<std::size_t>(n);
  } else if (n == 0) {
    r.closed = true;
  } else {
    const int err = ::WSAGetLastError();
    if (err != WSAEWOULDBLOCK && err != WSAEINTR) return failed_step(err);
    r.want_read = true;
  }
  return r;
}

IoStep send_some(int socket, const char* buf, std::size_t size) {
  IoStep r;
  const int n = ::send(w32::to_socket(socket), buf, static_cast<int>(size), 0);
  if (n >= 0) {
    r.n = static_cast<std::size_t>(n);
    if (n == 0) r.want_write = true;
  } else {
    const int err = ::WSAGetLastError();
    if (err != WSAEWOULDBLOCK && err != WSAEINTR) return failed_step(err);
    r.want_write = true;
  }
  return r;
}

void send_now(int socket, const std::string& bytes) {
  // Accepted sockets are non-blocking (accept_one): this never waits.
  [[maybe_unused]] auto n =
      ::send(w32::to_socket(socket), bytes.data(), static_cast<int>(bytes.size()), 0);
}

void close_socket(int socket) {
  if (socket != -1) ::closesocket(w32::to_socket(socket));
}

bool is_loopback_address(const std::string& host) {
  in_addr v4{};
  if (::inet_pton(AF_INET, host.c_str(), &v4) == 1) return (ntohl(v4.s_addr) >> 24) == 127;
  in6_addr v6{};
  if (::inet_pton(AF_INET6, host.c_str(), &v6) != 1) return false;
  for (int i = 0; i < 15; ++i)
    if (v6.s6_addr[i] != 0) return false;
  return v6.s6_addr[15] == 1;
}

void ignore_broken_pipe() {}  // Winsock's send never raises a signal

Waker::~Waker() {
  if (rx_ != -1) ::closesocket(w32::to_socket(rx_));
  if (tx_ != -1) ::closesocket(w32::to_socket(tx_));
}

// Two loopback datagram sockets connected to each other: WSAPoll waits on
// sockets only, so the wake-up is a datagram (POSIX uses a pipe). Connected,
// the receiving one takes datagrams from the sending one only.
Result<void> Waker::open() {
  LMCFG_TRY(w32::winsock_ready());
  const auto cannot = [] {
    return Error(Errc::io_error, "cannot create the server's wake-up sockets: " +
                                     w32::wsa_text(::WSAGetLastError()));
  };
  SOCKET rx =
      ::WSASocketW(AF_INET, SOCK_DGRAM, IPPROTO_UDP, nullptr, 0, WSA_FLAG_NO_HANDLE_INHERIT);
  SOCKET tx =
      ::WSASocketW(AF_INET, SOCK_DGRAM, IPPROTO_UDP, nullptr, 0, WSA_FLAG_NO_HANDLE_INHERIT);
  rx_ = w32::from_socket(rx);
  tx_ = w32::from_socket(tx);
  if (rx == INVALID_SOCKET || tx == INVALID_SOCKET) return cannot();
  sockaddr_in lo{};
  lo.sin_family = AF_INET;
  lo.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  lo.sin_port = 0;
  if (::bind(rx, reinterpret_cast<sockaddr*>(&lo), sizeof lo) != 0 ||
      ::bind(tx, reinterpret_cast<sockaddr*>(&lo), sizeof lo) != 0)
    return cannot();
  sockaddr_in rx_addr = lo, tx_addr = lo;
  rx_addr.sin_port = htons(static_cast<u_short>(port_of(rx)));
  tx_addr.sin_port = htons(static_cast<u_short>(port_of(tx)));
  if (::connect(tx, reinterpret_cast<sockaddr*>(&rx_addr), sizeof rx_addr) != 0 ||
      ::connect(rx, reinterpret_cast<sockaddr*>(&tx_addr), sizeof tx_addr) != 0)
    return cannot();
  set_nonblocking(rx);
  set_nonblocking(tx);
  return {};
}

void Waker::poke() const {
  const char c = 1;
  ::send(w32::to_socket(tx_), &c, 1, 0);  // a full queue wakes the loop already
}

void Waker::drain() const {
  char drain[256];
  while (::recv(w32::to_socket(rx_), drain, sizeof drain, 0) > 0) {
  }
}

bool wait_sockets(std::vector<Watch>& watches, int timeout_ms) {
  std::vector<WSAPOLLFD> fds;
  fds.reserve(watches.size());
  for (const Watch& w : watches) {
    WSAPOLLFD p{};
    p.fd = w32::to_socket(w.socket);
    p.events = static_cast<SHORT>((w.read ? POLLRDNORM : 0) | (w.write ? POLLWRNORM : 0));
    fds.push_back(p);
  }
  const int n = ::WSAPoll(fds.data(), static_cast<ULONG>(fds.size()), timeout_ms);
  for (std::size_t i = 0; i < fds.size(); ++i) {
    const SHORT re = n > 0 ? fds[i].revents : 0;
    watches[i].readable = re & POLLRDNORM;
    watches[i].writable = re & POLLWRNORM;
    watches[i].hangup = re & POLLHUP;
    watches[i].failed = re & (POLLERR | POLLNVAL);
  }
  return n != SOCKET_ERROR;
}

}  // namespace lmcfg::web

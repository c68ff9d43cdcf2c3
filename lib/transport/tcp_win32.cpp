// Windows: the TCP client of tcp.cpp on Winsock (serial-to-Ethernet gateways,
// and RFC 2217 through connect_tcp): a non-blocking connect with a deadline,
// TCP_NODELAY and SO_KEEPALIVE as on Linux; the messages are tcp.cpp's with
// Windows' error texts.
#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"
#include "transport/winsock_win32.hpp"

namespace lmcfg::transport {

namespace {

// Connects one resolved address; 0 on success, otherwise the WSA error
// (WSAETIMEDOUT at the deadline).
int connect_one(const addrinfo& ai, Clock::time_point deadline, UniqueFd& out) {
  const SOCKET s = ::WSASocketW(ai.ai_family, ai.ai_socktype, ai.ai_protocol, nullptr, 0,
                                WSA_FLAG_NO_HANDLE_INHERIT);
  if (s == INVALID_SOCKET) return ::WSAGetLastError();
  UniqueFd fd(win32::from_socket(s));
  u_long nonblocking = 1;
  if (::ioctlsocket(s, FIONBIO, &nonblocking) != 0) return ::WSAGetLastError();
  if (::connect(s, ai.ai_addr, static_cast<int>(ai.ai_addrlen)) != 0) {
    const int err = ::WSAGetLastError();
    if (err != WSAEWOULDBLOCK && err != WSAEINPROGRESS) return err;
    for (;;) {
      const int r = win32::wait_socket(s, true, detail::ms_left(deadline));
      if (r == SOCKET_ERROR) return ::WSAGetLastError();
      if (r == 0) {
        if (Clock::now() >= deadline) return WSAETIMEDOUT;
        continue;
      }
      break;
    }
    int soerr = 0;
    int len = sizeof soerr;
    if (::getsockopt(s, SOL_SOCKET, SO_ERROR, reinterpret_cast<char*>(&soerr), &len) != 0)
      return ::WSAGetLastError();
    if (soerr != 0) return soerr;
  }
  const BOOL one = TRUE;
  ::setsockopt(s, IPPROTO_TCP, TCP_NODELAY, reinterpret_cast<const char*>(&one), sizeof one);
  ::setsockopt(s, SOL_SOCKET, SO_KEEPALIVE, reinterpret_cast<const char*>(&one), sizeof one);
  out = std::move(fd);
  return 0;
}

}  // namespace

Result<TcpConnection> connect_tcp(const std::string& host, std::uint16_t port,
                                  Millis connect_timeout, const std::string& scheme) {
  LMCFG_ASSIGN_OR_RETURN(auto target, detail::tcp_target(host, port, scheme));
  const std::string& name = target.name;
  const std::string& where = target.where;
  LMCFG_TRY(win32::winsock_ready());

  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_protocol = IPPROTO_TCP;
  hints.ai_flags = AI_NUMERICSERV;
  addrinfo* res = nullptr;
  const std::string service = std::to_string(port);
  const int rc = ::getaddrinfo(name.c_str(), service.c_str(), &hints, &res);
  if (rc != 0 || res == nullptr) {
    return Error(Errc::not_found,
                 scheme + " " + where + ": cannot resolve host: " + win32::wsa_text(rc));
  }
  std::unique_ptr<addrinfo, decltype(&::freeaddrinfo)> list(res, &::freeaddrinfo);

  const auto deadline = Clock::now() + std::max(connect_timeout, Millis(0));
  int last = WSAECONNREFUSED;
  for (const addrinfo* ai = list.get(); ai != nullptr; ai = ai->ai_next) {
    UniqueFd fd;
    last = connect_one(*ai, deadline, fd);
    if (last == 0) return TcpConnection{std::move(fd), where};
    if (last == WSAETIMEDOUT) break;
  }
  if (last == WSAETIMEDOUT) {
    return Error(Errc::timeout, scheme + " " + where + ": connect timed out after " +
                                    std::to_string(connect_timeout.count()) + " ms");
  }
  return Error(Errc::io_error, scheme + " " + where + ": cannot connect: " + win32::wsa_text(last));
}

}  // namespace lmcfg::transport

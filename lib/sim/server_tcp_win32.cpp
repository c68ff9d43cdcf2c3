// Windows: the simulator's TCP listener (lmcfg sim --tcp) on Winsock; the
// accepted socket is served by FdTransport as on Linux (server_tcp.cpp).
#include "sim/server.hpp"
#include "transport/winsock_win32.hpp"

namespace lmcfg::sim {

namespace ws = transport::win32;

Result<transport::UniqueFd> listen_tcp(const std::string& host, std::uint16_t port,
                                       std::uint16_t& bound_port) {
  LMCFG_TRY(ws::winsock_ready());
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  if (::inet_pton(AF_INET, host.c_str(), &addr.sin_addr) != 1)
    return Error(Errc::invalid_argument, "listen address '" + host + "' is not an IPv4 address");
  const SOCKET s =
      ::WSASocketW(AF_INET, SOCK_STREAM, IPPROTO_TCP, nullptr, 0, WSA_FLAG_NO_HANDLE_INHERIT);
  if (s == INVALID_SOCKET)
    return Error(Errc::io_error, "socket: " + ws::wsa_text(::WSAGetLastError()));
  transport::UniqueFd fd(ws::from_socket(s));
  // No SO_REUSEADDR: on Windows it would let another program take the same
  // port; SO_EXCLUSIVEADDRUSE is Windows' "nobody else".
  const BOOL one = TRUE;
  ::setsockopt(s, SOL_SOCKET, SO_EXCLUSIVEADDRUSE, reinterpret_cast<const char*>(&one), sizeof one);
  if (::bind(s, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0)
    return Error(Errc::io_error, "bind " + host + ":" + std::to_string(port) + ": " +
                                     ws::wsa_text(::WSAGetLastError()));
  if (::listen(s, 4) != 0)
    return Error(Errc::io_error, "listen: " + ws::wsa_text(::WSAGetLastError()));
  int len = sizeof addr;
  if (::getsockname(s, reinterpret_cast<sockaddr*>(&addr), &len) != 0)
    return Error(Errc::io_error, "getsockname: " + ws::wsa_text(::WSAGetLastError()));
  bound_port = ntohs(addr.sin_port);
  return fd;
}

Result<transport::UniqueFd> accept_client(int listen_fd, transport::Millis timeout) {
  const SOCKET l = ws::to_socket(listen_fd);
  const int rc = ws::wait_socket(l, false, static_cast<int>(timeout.count()));
  if (rc == SOCKET_ERROR)
    return Error(Errc::io_error, "select: " + ws::wsa_text(::WSAGetLastError()));
  if (rc == 0) return transport::UniqueFd();
  const SOCKET c = ::accept(l, nullptr, nullptr);
  if (c == INVALID_SOCKET) {
    const int err = ::WSAGetLastError();
    if (err == WSAEWOULDBLOCK || err == WSAEINTR || err == WSAECONNRESET)
      return transport::UniqueFd();
    return Error(Errc::io_error, "accept: " + ws::wsa_text(err));
  }
  ::SetHandleInformation(reinterpret_cast<HANDLE>(c), HANDLE_FLAG_INHERIT, 0);
  return transport::UniqueFd(ws::from_socket(c));
}

}  // namespace lmcfg::sim

#pragma once
// Winsock plumbing shared by the Win32 socket files (tcp_win32.cpp,
// fd_transport_win32.cpp, udp_win32.cpp, the simulator's listener); never
// included on POSIX.
//
// A SOCKET is kept in the transports' UniqueFd (an int): Windows kernel
// handles have 32 significant bits, "it is safe to truncate the handle ... or
// sign extend the handle" (Microsoft, "Interprocess Communication Between
// 32-bit and 64-bit Applications"), and INVALID_SOCKET truncates to -1,
// UniqueFd's "none".
#ifndef WIN32_LEAN_AND_MEAN
#define WIN32_LEAN_AND_MEAN
#endif
#include <winsock2.h>
#include <ws2tcpip.h>

#include <chrono>
#include <string>

#include "common/result.hpp"
#include "transport/win32_util.hpp"

namespace lmcfg::transport::win32 {

// WSAStartup(2.2) once per process (the result is kept: a failure is reported
// by every later call too). Never paired with WSACleanup: the process's exit
// releases Winsock.
inline Result<void> winsock_ready() {
  static const int rc = [] {
    WSADATA data{};
    return ::WSAStartup(MAKEWORD(2, 2), &data);
  }();
  if (rc != 0)
    return Error(Errc::io_error, "Winsock 2.2 could not be started (WSAStartup): " +
                                     error_text(static_cast<DWORD>(rc)));
  return {};
}

inline SOCKET to_socket(int fd) noexcept {
  return static_cast<SOCKET>(static_cast<INT_PTR>(fd));  // sign extension keeps -1
}
inline int from_socket(SOCKET s) noexcept { return static_cast<int>(static_cast<INT_PTR>(s)); }

// WSAGetLastError() as FormatMessage's text ("No connection could be made
// because the target machine actively refused it").
inline std::string wsa_text(int err) { return error_text(static_cast<DWORD>(err)); }

// Waits until `s` is readable (or writable) or `ms` passed: 1 ready, 0 not,
// SOCKET_ERROR on failure. select() rather than WSAPoll: WSAPoll does not
// report a failed connect before Windows 10 2004, and one socket is all there is.
// A connect's failure shows in the exception set, counted as ready.
inline int wait_socket(SOCKET s, bool for_write, int ms) {
  fd_set set;
  FD_ZERO(&set);
  FD_SET(s, &set);
  fd_set except;
  FD_ZERO(&except);
  FD_SET(s, &except);
  timeval tv{ms / 1000, (ms % 1000) * 1000};
  return ::select(0, for_write ? nullptr : &set, for_write ? &set : nullptr, &except, &tv);
}

}  // namespace lmcfg::transport::win32

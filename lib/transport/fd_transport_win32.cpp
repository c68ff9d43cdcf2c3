// Windows: FdTransport over a connected Winsock socket, the only descriptor
// this build serves (no pseudo-terminals, and COM ports are serial_win32.cpp's
// handles). UniqueFd holds the SOCKET (winsock_win32.hpp). The deadlines are
// fd_transport.cpp's: write within max(5 s, twice the wire time), read_some
// waits up to its timeout for the first byte, then drains what is there.
#include <algorithm>
#include <array>

#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"
#include "transport/winsock_win32.hpp"

namespace lmcfg::transport {

namespace {

constexpr std::size_t kChunk = 4096;
constexpr std::size_t kMaxDrain = 1 << 20;  // read_some / discard_input stop after 1 MiB

bool is_closed_error(int err) {
  return err == WSAECONNRESET || err == WSAECONNABORTED || err == WSAENETRESET ||
         err == WSAESHUTDOWN || err == WSAENOTCONN;
}

}  // namespace

void UniqueFd::reset(int fd) noexcept {
  if (fd_ >= 0) ::closesocket(win32::to_socket(fd_));
  fd_ = fd;
}

FdTransport::FdTransport(UniqueFd fd, std::string description, double byte_time_us)
    : fd_(std::move(fd)), description_(std::move(description)), byte_time_us_(byte_time_us) {
  if (!fd_) return;
  u_long nonblocking = 1;
  ::ioctlsocket(win32::to_socket(fd_.get()), FIONBIO, &nonblocking);
  is_socket_ = true;
}

Error FdTransport::os_error(const char* what, int err) const {
  const Errc code = is_closed_error(err) ? Errc::link_closed : Errc::io_error;
  return Error(code, description_ + ": " + what + ": " + win32::wsa_text(err));
}

Result<void> FdTransport::write(ByteView bytes) {
  if (!fd_) return Error(Errc::link_closed, description_ + ": link is closed");
  const SOCKET s = win32::to_socket(fd_.get());
  Millis limit = write_timeout_;
  if (limit.count() <= 0) {
    const double wire_ms = 2.0 * byte_time_us_ * static_cast<double>(bytes.size()) / 1000.0;
    limit = std::max(Millis(5000), Millis(static_cast<long long>(wire_ms) + 1));
  }
  const auto deadline = Clock::now() + limit;
  std::size_t off = 0;
  while (off < bytes.size()) {
    const auto* p = reinterpret_cast<const char*>(bytes.data() + off);
    const int len = static_cast<int>(std::min<std::size_t>(bytes.size() - off, 1 << 20));
    const int n = ::send(s, p, len, 0);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    const int err = n < 0 ? ::WSAGetLastError() : 0;
    if (n < 0 && err != WSAEWOULDBLOCK && err != WSAEINTR) return os_error("write failed", err);
    const int r = win32::wait_socket(s, true, detail::ms_left(deadline));
    if (r == SOCKET_ERROR) return os_error("select failed", ::WSAGetLastError());
    if (r == 0 && Clock::now() >= deadline) {
      return Error(Errc::timeout, description_ + ": write timed out after " +
                                      std::to_string(limit.count()) + " ms (" +
                                      std::to_string(off) + " of " + std::to_string(bytes.size()) +
                                      " bytes written)");
    }
  }
  return {};
}

Result<Bytes> FdTransport::read_some(Millis timeout) {
  if (!fd_) return Error(Errc::link_closed, description_ + ": link is closed");
  const SOCKET s = win32::to_socket(fd_.get());
  const auto deadline = Clock::now() + std::max(timeout, Millis(0));
  std::array<char, kChunk> buf{};
  for (;;) {
    const int r = win32::wait_socket(s, false, detail::ms_left(deadline));
    if (r == SOCKET_ERROR) return os_error("select failed", ::WSAGetLastError());
    if (r == 0) {
      if (Clock::now() >= deadline) return Bytes{};
      continue;
    }
    Bytes out;
    while (out.size() < kMaxDrain) {
      const int n = ::recv(s, buf.data(), static_cast<int>(buf.size()), 0);
      if (n > 0) {
        out.insert(out.end(), buf.begin(), buf.begin() + n);
        continue;
      }
      if (!out.empty())
        break;  // deliver what came before an end or error; the next call reports it
      if (n == 0) return Error(Errc::link_closed, description_ + ": peer closed the connection");
      const int err = ::WSAGetLastError();
      if (err == WSAEWOULDBLOCK || err == WSAEINTR) break;
      return os_error("read failed", err);
    }
    if (!out.empty()) return out;
    if (Clock::now() >= deadline) return Bytes{};
    // Spurious wake-up without data: wait again for the rest of the timeout.
  }
}

void FdTransport::discard_input() {
  if (!fd_) return;
  const SOCKET s = win32::to_socket(fd_.get());
  std::array<char, kChunk> buf{};
  for (std::size_t total = 0; total < kMaxDrain;) {
    const int n = ::recv(s, buf.data(), static_cast<int>(buf.size()), 0);
    if (n <= 0) break;
    total += static_cast<std::size_t>(n);
  }
}

}  // namespace lmcfg::transport

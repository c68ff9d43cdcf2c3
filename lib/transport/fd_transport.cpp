// FdTransport and UniqueFd: poll()-based byte moving over one descriptor.
#include <errno.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>

#include "transport/pty.hpp"
#include "transport/tcp_common.hpp"

namespace lmcfg::transport {

namespace {

constexpr std::size_t kChunk = 4096;
constexpr std::size_t kMaxDrain = 1 << 20;  // read_some / discard_input stop after 1 MiB

bool is_closed_errno(int err) { return err == EIO || err == EPIPE || err == ECONNRESET; }

}  // namespace

void UniqueFd::reset(int fd) noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

FdTransport::FdTransport(UniqueFd fd, std::string description, double byte_time_us)
    : fd_(std::move(fd)), description_(std::move(description)), byte_time_us_(byte_time_us) {
  if (!fd_) return;
  const int fl = ::fcntl(fd_.get(), F_GETFL);
  if (fl >= 0 && (fl & O_NONBLOCK) == 0) ::fcntl(fd_.get(), F_SETFL, fl | O_NONBLOCK);
  is_tty_ = ::isatty(fd_.get()) == 1;
  struct stat st {};
  is_socket_ = ::fstat(fd_.get(), &st) == 0 && S_ISSOCK(st.st_mode);
}

Error FdTransport::os_error(const char* what, int err) const {
  const Errc code = is_closed_errno(err) ? Errc::link_closed : Errc::io_error;
  return Error(code, description_ + ": " + what + ": " + std::strerror(err));
}

Result<void> FdTransport::write(ByteView bytes) {
  if (!fd_) return Error(Errc::link_closed, description_ + ": link is closed");
  Millis limit = write_timeout_;
  if (limit.count() <= 0) {
    const double wire_ms = 2.0 * byte_time_us_ * static_cast<double>(bytes.size()) / 1000.0;
    limit = std::max(Millis(5000), Millis(static_cast<long long>(wire_ms) + 1));
  }
  const auto deadline = Clock::now() + limit;
  std::size_t off = 0;
  while (off < bytes.size()) {
    const auto* p = bytes.data() + off;
    const std::size_t len = bytes.size() - off;
    const ssize_t n = is_socket_ ? ::send(fd_.get(), p, len, MSG_NOSIGNAL | MSG_DONTWAIT)
                                 : ::write(fd_.get(), p, len);
    if (n > 0) {
      off += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    if (n < 0 && errno != EAGAIN && errno != EWOULDBLOCK) return os_error("write failed", errno);
    // No room (or a zero-byte write): wait for POLLOUT until the deadline.
    pollfd pfd{fd_.get(), POLLOUT, 0};
    const int r = ::poll(&pfd, 1, detail::ms_left(deadline));
    if (r < 0 && errno != EINTR) return os_error("poll failed", errno);
    if (r == 0 && Clock::now() >= deadline) {
      return Error(Errc::timeout, description_ + ": write timed out after " +
                                      std::to_string(limit.count()) + " ms (" +
                                      std::to_string(off) + " of " + std::to_string(bytes.size()) +
                                      " bytes written)");
    }
    if (r > 0 && (pfd.revents & POLLNVAL) != 0)
      return Error(Errc::io_error, description_ + ": write failed: descriptor is not open");
  }
  return {};
}

Result<Bytes> FdTransport::read_some(Millis timeout) {
  if (!fd_) return Error(Errc::link_closed, description_ + ": link is closed");
  const auto deadline = Clock::now() + std::max(timeout, Millis(0));
  std::array<std::uint8_t, kChunk> buf{};
  // Acknowledge what arrives at once (Linux clears the flag by itself, so it
  // is set before each wait): a serial server that holds its next segment
  // until the last is acknowledged (Nagle's rule; ser2net answers an RFC 2217
  // purge, then the drive's answer) otherwise waits out our delayed
  // acknowledgement, 40 ms per exchange. Not a TCP socket: the call fails, harmless.
  if (is_socket_) {
    const int one = 1;
    ::setsockopt(fd_.get(), IPPROTO_TCP, TCP_QUICKACK, &one, sizeof one);
  }
  for (;;) {
    pollfd pfd{fd_.get(), POLLIN, 0};
    const int r = ::poll(&pfd, 1, detail::ms_left(deadline));
    if (r < 0) {
      if (errno == EINTR) continue;
      return os_error("poll failed", errno);
    }
    if (r == 0) {
      if (Clock::now() >= deadline) return Bytes{};
      continue;
    }
    if ((pfd.revents & POLLNVAL) != 0)
      return Error(Errc::io_error, description_ + ": read failed: descriptor is not open");
    const bool hangup = (pfd.revents & (POLLHUP | POLLERR)) != 0;

    Bytes out;
    while (out.size() < kMaxDrain) {
      const ssize_t n = is_socket_ ? ::recv(fd_.get(), buf.data(), buf.size(), MSG_DONTWAIT)
                                   : ::read(fd_.get(), buf.data(), buf.size());
      if (n > 0) {
        out.insert(out.end(), buf.begin(), buf.begin() + n);
        continue;
      }
      if (n < 0 && errno == EINTR) continue;
      if (!out.empty())
        break;  // deliver what came before an end or error; the next call reports it
      if (n == 0) {
        // A terminal in raw mode with VMIN=0/VTIME=0 also returns 0 for "no data";
        // it is the end only when poll reported a hang-up.
        if (!is_tty_ || hangup)
          return Error(
              Errc::link_closed,
              description_ + (is_socket_ ? ": peer closed the connection" : ": device hung up"));
        break;
      }
      if (errno == EAGAIN || errno == EWOULDBLOCK) break;
      if (errno == EIO && is_tty_)
        return Error(Errc::link_closed,
                     description_ + ": device hung up (" + std::strerror(EIO) + ")");
      return os_error("read failed", errno);
    }
    if (!out.empty()) return out;
    if (Clock::now() >= deadline) return Bytes{};
    // Spurious wake-up without data: wait again for the rest of the timeout.
  }
}

void FdTransport::discard_input() {
  if (!fd_) return;
  if (is_tty_) {
    ::tcflush(fd_.get(), TCIFLUSH);
    return;
  }
  std::array<std::uint8_t, kChunk> buf{};
  for (std::size_t total = 0; total < kMaxDrain;) {
    const ssize_t n = is_socket_ ? ::recv(fd_.get(), buf.data(), buf.size(), MSG_DONTWAIT)
                                 : ::read(fd_.get(), buf.data(), buf.size());
    if (n > 0) {
      total += static_cast<std::size_t>(n);
      continue;
    }
    if (n < 0 && errno == EINTR) continue;
    break;
  }
}

}  // namespace lmcfg::transport

#pragma once
// File-descriptor plumbing shared by the POSIX transports, and pseudo-terminals
// for tests and for serving a simulated drive on a pty (the client opens the
// slave path with open_serial, the server serves the master with FdTransport).
#include <string>
#include <utility>

#include "transport/transport.hpp"

struct termios;

namespace lmcfg::transport {

// The line settings open_serial applies, on top of `t` (from tcgetattr):
// cfmakeraw, CS8, parity and stop bits from `s`, CLOCAL|CREAD, no RTS/CTS or
// XON/XOFF, no input parity check, VMIN=0/VTIME=0, both speeds. `s` must validate().
void make_serial_termios(::termios& t, const SerialSettings& s);
// True for a pseudo-terminal slave (/dev/pts/N). Linux ptys force CS8 and
// clear PARENB whatever is asked, so open_serial does not insist on parity there.
bool is_pty_slave(int fd);

// The output speed of a terminal as one of kSerialBaudRates; nullopt when it is
// another speed or `fd` is not a terminal. On Linux the master side of a
// pseudo-terminal reports the speed its slave was set to, which lets the
// simulated drive hear only a master that talks at the drive's baud rate.
std::optional<unsigned> line_baud(int fd);

// Owns one file descriptor; closes it on destruction. Move-only.
class UniqueFd {
 public:
  UniqueFd() = default;
  explicit UniqueFd(int fd) noexcept : fd_(fd) {}
  UniqueFd(UniqueFd&& o) noexcept : fd_(o.release()) {}
  UniqueFd& operator=(UniqueFd&& o) noexcept {
    if (this != &o) reset(o.release());
    return *this;
  }
  UniqueFd(const UniqueFd&) = delete;
  UniqueFd& operator=(const UniqueFd&) = delete;
  ~UniqueFd() { reset(); }

  int get() const noexcept { return fd_; }
  bool valid() const noexcept { return fd_ >= 0; }
  explicit operator bool() const noexcept { return valid(); }
  int release() noexcept { return std::exchange(fd_, -1); }
  void reset(int fd = -1) noexcept;

 private:
  int fd_ = -1;
};

// Transport over an already-open descriptor: a pty master, a tty, a connected
// socket, a pipe. The descriptor is switched to O_NONBLOCK; waits use poll().
//  - write: all bytes, waiting for room at most write_timeout (default
//    max(5 s, twice the wire time)); Errc::timeout when the peer does not drain.
//  - read_some: waits up to the timeout for the first byte, then drains what is
//    immediately available. End of file, hang-up (EIO on a pty master whose
//    slave is closed), EPIPE and ECONNRESET give Errc::link_closed.
//  - discard_input: tcflush(TCIFLUSH) on a terminal, otherwise reads and drops
//    what is immediately available.
// Sockets are written with send(MSG_NOSIGNAL), so a closed peer never raises SIGPIPE.
// Error messages start with `description` ("serial /dev/ttyUSB0 57600 8N1: ...").
class FdTransport : public Transport {
 public:
  FdTransport(UniqueFd fd, std::string description, double byte_time_us = 0.0);
  ~FdTransport() override = default;

  Result<void> write(ByteView bytes) override;
  Result<Bytes> read_some(Millis timeout) override;
  void discard_input() override;
  std::string describe() const override { return description_; }
  double byte_time_us() const override { return byte_time_us_; }

  int fd() const noexcept { return fd_.get(); }
  // Zero (the default) means max(5 s, twice the wire time of the chunk).
  void set_write_timeout(Millis t) { write_timeout_ = t; }
  // Closes the descriptor now; later calls give Errc::link_closed.
  void close() { fd_.reset(); }

 protected:
  void set_line_description(std::string description, double byte_time_us) {
    description_ = std::move(description);
    byte_time_us_ = byte_time_us;
  }

 private:
  Error os_error(const char* what, int err) const;

  UniqueFd fd_;
  std::string description_;
  double byte_time_us_ = 0.0;
  Millis write_timeout_{0};
  bool is_tty_ = false;
  bool is_socket_ = false;
};

// A connected TCP socket (non-blocking, TCP_NODELAY, SO_KEEPALIVE) and
// "host:port" as messages name it ("[::1]:4001" for IPv6).
struct TcpConnection {
  UniqueFd fd;
  std::string where;
};
// Resolves `host` and connects within `connect_timeout`; errors start with
// "`scheme` host:port: " ("tcp 10.0.0.5:4001: connect timed out after 2000 ms").
// Shared by open_tcp and open_rfc2217.
Result<TcpConnection> connect_tcp(const std::string& host, std::uint16_t port,
                                  Millis connect_timeout, const std::string& scheme);

struct PtyPair {
  UniqueFd master;         // raw mode, O_NONBLOCK, close-on-exec
  UniqueFd slave;          // kept open so the master does not see a hang-up while no
                           // client has the slave open; reset() it to drop it
  std::string slave_path;  // "/dev/pts/7": give this to open_serial
};
// openpty(3); both ends raw (cfmakeraw on the shared line settings), close-on-exec.
Result<PtyPair> open_pty();

}  // namespace lmcfg::transport

#pragma once
// What lmcfg serve's HTTP server needs from the operating system's sockets
// (web_socket.cpp: POSIX poll and a wake-up pipe; web_socket_win32.cpp:
// Winsock's WSAPoll and a loopback datagram socket that wakes it): a
// non-blocking listener, its accepted connections, their reads and writes,
// and one wait over all of them. Private to the web layer.
//
// A socket is an int on both platforms: a POSIX descriptor, or a Winsock
// SOCKET kept as transport/winsock_win32.hpp keeps it (Windows handles have
// 32 significant bits; INVALID_SOCKET truncates to -1).
#include <cstddef>
#include <string>
#include <vector>

#include "common/result.hpp"

namespace lmcfg::web {

// What a non-blocking step did: `n` bytes moved (0 with want_*: try again
// when the socket is readable/writable); `closed`: the peer closed or the
// connection failed (`error` says why, "" for an orderly close).
struct IoStep {
  std::size_t n = 0;
  bool want_read = false, want_write = false, closed = false;
  std::string error;
};

// HOST:PORT bound and listening, non-blocking (port 0: any free one), and the
// port bound. Never shared with another process: no SO_REUSEPORT on POSIX,
// SO_EXCLUSIVEADDRUSE on Windows (where SO_REUSEADDR would let a second
// server take the port). Errc::io_error naming the address otherwise.
struct Listener {
  int socket = -1;
  int port = 0;
};
Result<Listener> listen_on(const std::string& host, int port);

// One waiting connection, non-blocking with TCP_NODELAY, and its peer's
// address as text ("::ffff:" removed from an IPv4 peer's). -1 when none waits.
int accept_one(int listener, std::string& peer);

IoStep recv_some(int socket, char* buf, std::size_t size);
IoStep send_some(int socket, const char* buf, std::size_t size);
// Sends what the socket takes now, without waiting, and ignores failures
// (a 503 to a connection about to be closed).
void send_now(int socket, const std::string& bytes);
void close_socket(int socket);

// True for a numeric loopback address (127.0.0.0/8, ::1); names are not
// resolved: "127.example.com" is whatever its DNS says.
bool is_loopback_address(const std::string& host);

// A client closing while its answer is written must not end the process
// (POSIX: SIGPIPE ignored; Windows has no such signal).
void ignore_broken_pipe();

// The event loop's wait: each watched socket with what to watch for, and
// after wait_sockets() what it is ready for.
struct Watch {
  int socket = -1;
  bool read = false, write = false;
  bool readable = false, writable = false, hangup = false, failed = false;
};

// Lets another thread end the event loop's wait (a worker's answer is ready,
// stop() was called).
class Waker {
 public:
  Waker() = default;
  ~Waker();
  Waker(const Waker&) = delete;
  Waker& operator=(const Waker&) = delete;
  Result<void> open();
  void poke() const;  // from any thread; never blocks
  void drain() const;
  int socket() const { return rx_; }  // watch it for reading

 private:
  int rx_ = -1, tx_ = -1;
};

// Waits until a watched socket is ready or `timeout_ms` passed (0: look
// only); fills readable/writable/hangup/failed. false when the wait itself
// failed (not when it was interrupted by a signal).
bool wait_sockets(std::vector<Watch>& watches, int timeout_ms);

}  // namespace lmcfg::web

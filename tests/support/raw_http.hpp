#pragma once
// A raw TCP client for the HTTP server's tests: sends exactly the bytes given
// (slow, malformed, hostile), reads what comes back with a deadline, and
// tells whether the server closed the connection. From any loopback address
// (127.0.0.2 ...), so that tests can play several client hosts. POSIX
// sockets, or Winsock in the Windows build's tests (run under Wine).
#ifdef _WIN32
#include "transport/winsock_win32.hpp"
#else
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>
#endif

#include <chrono>
#include <string>

namespace lmcfg::test {

#ifdef _WIN32
namespace raw_socket {
inline int open_stream() {
  (void)lmcfg::transport::win32::winsock_ready();
  return lmcfg::transport::win32::from_socket(::socket(AF_INET, SOCK_STREAM, 0));
}
inline SOCKET s(int fd) { return lmcfg::transport::win32::to_socket(fd); }
inline void close_fd(int fd) { ::closesocket(s(fd)); }
inline int poll_in(int fd, int ms) {
  WSAPOLLFD p{};
  p.fd = s(fd);
  p.events = POLLRDNORM;
  return ::WSAPoll(&p, 1, ms);
}
inline long long send_all(int fd, const std::string& b) {
  return ::send(s(fd), b.data(), static_cast<int>(b.size()), 0);
}
inline long long recv_some(int fd, char* buf, std::size_t n) {
  return ::recv(s(fd), buf, static_cast<int>(n), 0);
}
}  // namespace raw_socket
#else
namespace raw_socket {
inline int open_stream() { return ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0); }
inline int s(int fd) { return fd; }
inline void close_fd(int fd) { ::close(fd); }
inline int poll_in(int fd, int ms) {
  pollfd p{fd, POLLIN, 0};
  return ::poll(&p, 1, ms);
}
inline long long send_all(int fd, const std::string& b) {
  return ::send(fd, b.data(), b.size(), MSG_NOSIGNAL);
}
inline long long recv_some(int fd, char* buf, std::size_t n) { return ::recv(fd, buf, n, 0); }
}  // namespace raw_socket
#endif

class RawClient {
 public:
  explicit RawClient(int port, const char* from = nullptr) {
    fd_ = raw_socket::open_stream();
    if (from) {
      sockaddr_in src{};
      src.sin_family = AF_INET;
      ::inet_pton(AF_INET, from, &src.sin_addr);
      ::bind(raw_socket::s(fd_), reinterpret_cast<sockaddr*>(&src), sizeof src);
    }
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    connected_ = ::connect(raw_socket::s(fd_), reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~RawClient() {
    if (fd_ != -1) raw_socket::close_fd(fd_);
  }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;
  RawClient(RawClient&& o) noexcept : fd_(o.fd_), connected_(o.connected_), closed_(o.closed_) {
    o.fd_ = -1;
  }

  bool connected() const { return connected_; }
  bool send(const std::string& bytes) {
    return raw_socket::send_all(fd_, bytes) == static_cast<long long>(bytes.size());
  }
  // What arrives within `ms`, stopping early when the server closes or when
  // `until` appears in what was read.
  std::string read(int ms, const std::string& until = "") {
    std::string out;
    const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(ms);
    while (!closed_) {
      const auto left = std::chrono::duration_cast<std::chrono::milliseconds>(
                            end - std::chrono::steady_clock::now())
                            .count();
      if (left <= 0 || !read_once(static_cast<int>(left), out)) break;
      if (!until.empty() && out.find(until) != std::string::npos) break;
    }
    return out;
  }
  // One whole answer (head and Content-Length body) within `ms`.
  std::string response(int ms) {
    std::string out = read(ms, "\r\n\r\n");
    const auto head_end = out.find("\r\n\r\n");
    if (head_end == std::string::npos) return out;
    const auto cl = out.find("Content-Length: ");
    if (cl == std::string::npos || cl > head_end) return out;
    const std::size_t len = std::stoul(out.substr(cl + 16));
    while (out.size() < head_end + 4 + len && !closed_ && read_once(ms, out)) {
    }
    return out;
  }
  // Whether the server has closed the connection (within `ms`).
  bool closed(int ms) {
    read(ms);
    return closed_;
  }

 private:
  // One poll and one read into `out`; false when nothing came within `ms`
  // or the server closed.
  bool read_once(int ms, std::string& out) {
    if (raw_socket::poll_in(fd_, ms) <= 0) return false;
    char buf[65536];
    const long long n = raw_socket::recv_some(fd_, buf, sizeof buf);
    if (n <= 0) {
      closed_ = true;
      return false;
    }
    out.append(buf, static_cast<std::size_t>(n));
    return true;
  }

  int fd_ = -1;
  bool connected_ = false, closed_ = false;
};

}  // namespace lmcfg::test

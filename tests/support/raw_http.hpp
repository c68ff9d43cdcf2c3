#pragma once
// A raw TCP client for the HTTP server's tests: sends exactly the bytes given
// (slow, malformed, hostile), reads what comes back with a deadline, and
// tells whether the server closed the connection. From any loopback address
// (127.0.0.2 ...), so that tests can play several client hosts.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <string>

namespace lmcfg::test {

class RawClient {
 public:
  explicit RawClient(int port, const char* from = nullptr) {
    fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    if (from) {
      sockaddr_in src{};
      src.sin_family = AF_INET;
      ::inet_pton(AF_INET, from, &src.sin_addr);
      ::bind(fd_, reinterpret_cast<sockaddr*>(&src), sizeof src);
    }
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(static_cast<std::uint16_t>(port));
    ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
    connected_ = ::connect(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
  }
  ~RawClient() {
    if (fd_ >= 0) ::close(fd_);
  }
  RawClient(const RawClient&) = delete;
  RawClient& operator=(const RawClient&) = delete;
  RawClient(RawClient&& o) noexcept : fd_(o.fd_), connected_(o.connected_), closed_(o.closed_) {
    o.fd_ = -1;
  }

  bool connected() const { return connected_; }
  bool send(const std::string& bytes) {
    return ::send(fd_, bytes.data(), bytes.size(), MSG_NOSIGNAL) ==
           static_cast<ssize_t>(bytes.size());
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
    pollfd p{fd_, POLLIN, 0};
    if (::poll(&p, 1, ms) <= 0) return false;
    char buf[65536];
    const ssize_t n = ::recv(fd_, buf, sizeof buf, 0);
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

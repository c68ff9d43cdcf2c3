#pragma once
// A line whose drive never answers: a TCP listener on 127.0.0.1 (an inventory
// line's port tcp://127.0.0.1:PORT, as a serial device server is reached)
// that takes every connection and every byte sent and answers nothing. A
// read on it waits for the line's full timeout; release() closes everything,
// so a read in progress ends at once (the peer closed) and later ones are
// refused. No Catch2 here: bench/bench_http_hostile.cpp uses it too. POSIX.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

namespace lmcfg::test {

class HungLine {
 public:
  HungLine() {
    listen_fd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (listen_fd_ < 0 || ::bind(listen_fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        ::listen(listen_fd_, 16) != 0 ||
        ::getsockname(listen_fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0)
      return;
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] { loop(); });
  }
  ~HungLine() { release(); }
  HungLine(const HungLine&) = delete;
  HungLine& operator=(const HungLine&) = delete;

  int port() const { return port_; }  // 0: no listener could be made
  // Connections taken so far.
  int connections() const { return accepted_; }

  void release() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    std::lock_guard<std::mutex> lock(mu_);
    for (int fd : conns_) ::close(fd);
    conns_.clear();
    if (listen_fd_ >= 0) ::close(listen_fd_);
    listen_fd_ = -1;
  }

 private:
  void loop() {
    while (!stop_) {
      std::vector<pollfd> fds{{listen_fd_, POLLIN, 0}};
      {
        std::lock_guard<std::mutex> lock(mu_);
        for (int fd : conns_) fds.push_back({fd, POLLIN, 0});
      }
      if (::poll(fds.data(), fds.size(), 50) <= 0) continue;
      if (fds[0].revents & POLLIN) {
        const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd >= 0) {
          std::lock_guard<std::mutex> lock(mu_);
          conns_.push_back(fd);
          ++accepted_;
        }
      }
      // What the master sends is read and dropped: the drive is deaf.
      for (std::size_t i = 1; i < fds.size(); ++i) {
        if (!(fds[i].revents & (POLLIN | POLLHUP))) continue;
        char buf[512];
        if (::recv(fds[i].fd, buf, sizeof buf, MSG_DONTWAIT) == 0) {
          std::lock_guard<std::mutex> lock(mu_);
          std::erase(conns_, fds[i].fd);
          ::close(fds[i].fd);
        }
      }
    }
  }

  int listen_fd_ = -1;
  int port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> accepted_{0};
  std::mutex mu_;
  std::vector<int> conns_;
  std::thread thread_;
};

}  // namespace lmcfg::test

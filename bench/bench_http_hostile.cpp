// lmcfg serve under hostile clients (docs/serve.md "Security model"): the real
// `lmcfg serve` program on 127.0.0.1 over two simulated drives, and this
// program as its clients, all on loopback. Prints:
//   - the answer time of a plain `GET /api/v1/drives` (a new connection each,
//     from 127.0.0.1) while 0, 50 and 200 hostile connections are held: a
//     third trickle a header byte per second (slowloris), a third made one
//     request and stay idle (keep-alive), a third never send a byte; spread
//     over 127.0.0.2-127.0.0.5 (the per-address limit is for one host);
//   - the same with 200 connections from the client's own address 127.0.0.1;
//   - four 128 MB chunked uploads without a token: what the service answered
//     and how many bytes it took before closing;
//   - the service's resident memory after each phase and its peak (VmHWM of
//     /proc/PID/status);
//   - a hung line (a drive that never answers, hung_line.hpp): 12 live diffs
//     and 4 plans of its position sent at once, how they were answered, and
//     meanwhile the answer times of other clients' `GET /api/v1/drives` and
//     `GET /metrics` (median, max).
// usage: lmcfg_bench_http_hostile [LMCFG_BINARY]  (default: the build's lmcfg)
// Not part of ctest; figures in docs/serve.md.
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <poll.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "hung_line.hpp"

namespace fs = std::filesystem;
using Steady = std::chrono::steady_clock;

namespace {

int connect_from(int port, const char* from) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in src{};
  src.sin_family = AF_INET;
  ::inet_pton(AF_INET, from, &src.sin_addr);
  ::bind(fd, reinterpret_cast<sockaddr*>(&src), sizeof src);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<std::uint16_t>(port));
  ::inet_pton(AF_INET, "127.0.0.1", &a.sin_addr);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
    ::close(fd);
    return -1;
  }
  return fd;
}

// Reads until the peer closes or `ms` pass; the bytes read.
std::string read_all(int fd, int ms) {
  std::string out;
  const auto end = Steady::now() + std::chrono::milliseconds(ms);
  while (Steady::now() < end) {
    pollfd p{fd, POLLIN, 0};
    const auto left =
        std::chrono::duration_cast<std::chrono::milliseconds>(end - Steady::now()).count();
    if (::poll(&p, 1, static_cast<int>(std::max<long>(left, 0))) <= 0) break;
    char buf[65536];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  return out;
}

// One GET of the drives on a new connection: milliseconds to the whole
// answer, or -1 when none came within 60 s.
double timed_get(int port) {
  const auto t0 = Steady::now();
  const int fd = connect_from(port, "127.0.0.1");
  if (fd < 0) return -1;
  const std::string req = "GET /api/v1/drives HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                          "\r\nConnection: close\r\n\r\n";
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  const std::string a = read_all(fd, 60000);
  ::close(fd);
  if (a.rfind("HTTP/1.1 200", 0) != 0) return -1;
  return std::chrono::duration<double, std::milli>(Steady::now() - t0).count();
}

long proc_kb(pid_t pid, const char* key) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stol(line.substr(std::strlen(key)));
  return -1;
}

struct Hostile {
  std::vector<int> trickle, idle, silent;
  std::atomic<bool> stop{false};
  std::thread thread;
  void close_all() {
    stop = true;
    if (thread.joinable()) thread.join();
    for (auto* v : {&trickle, &idle, &silent})
      for (int fd : *v) ::close(fd);
  }
};

// n hostile connections, a third of each kind, from `addrs` in turn.
void hold(Hostile& h, int port, int n, const std::vector<const char*>& addrs) {
  const std::string host = "Host: 127.0.0.1:" + std::to_string(port) + "\r\n";
  for (int i = 0; i < n; ++i) {
    const int fd = connect_from(port, addrs[static_cast<std::size_t>(i) % addrs.size()]);
    if (fd < 0) continue;
    if (i % 3 == 0) {
      ::send(fd, "GET /api/v1/drives HTTP/1.1\r\n", 29, MSG_NOSIGNAL);
      h.trickle.push_back(fd);
    } else if (i % 3 == 1) {
      const std::string req = "GET /metrics HTTP/1.1\r\n" + host + "\r\n";
      ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
      read_all(fd, 200);  // the answer; the connection stays open
      h.idle.push_back(fd);
    } else {
      h.silent.push_back(fd);
    }
  }
  h.thread = std::thread([&h] {
    while (!h.stop) {
      for (int fd : h.trickle) ::send(fd, "X", 1, MSG_NOSIGNAL | MSG_DONTWAIT);
      for (int i = 0; i < 10 && !h.stop; ++i)
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
}

// How many of the held connections the server has closed by now.
int closed_count(const std::vector<int>& fds) {
  int n = 0;
  for (int fd : fds) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, 0) > 0) {
      char c;
      if (::recv(fd, &c, 1, MSG_PEEK | MSG_DONTWAIT) == 0) ++n;
    }
  }
  return n;
}

void table_row(const char* what, int held, int port, pid_t pid, Hostile& h) {
  std::vector<double> ms;
  for (int i = 0; i < 20; ++i) ms.push_back(timed_get(port));
  std::sort(ms.begin(), ms.end());
  const int failed = static_cast<int>(std::count(ms.begin(), ms.end(), -1.0));
  const int closed = closed_count(h.trickle) + closed_count(h.idle) + closed_count(h.silent);
  std::printf("| %-34s | %4d | %4d | %8.1f | %8.1f | %6d | %7.1f |\n", what, held, held - closed,
              ms[10], ms.back(), failed, static_cast<double>(proc_kb(pid, "VmRSS:")) / 1024.0);
}

// One request on a new connection: milliseconds to the whole answer (-1: none
// within 60 s) and its status (0: none).
double timed_request(int port, const std::string& method, const std::string& path, int* status) {
  const auto t0 = Steady::now();
  *status = 0;
  const int fd = connect_from(port, "127.0.0.1");
  if (fd < 0) return -1;
  std::string req = method + " " + path + " HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
                    "\r\nConnection: close\r\n";
  if (method == "POST")
    req += "Content-Type: application/json\r\nContent-Length: 2\r\n\r\n{}";
  else
    req += "\r\n";
  ::send(fd, req.data(), req.size(), MSG_NOSIGNAL);
  const std::string a = read_all(fd, 60000);
  ::close(fd);
  if (a.rfind("HTTP/1.1 ", 0) != 0) return -1;
  *status = std::atoi(a.c_str() + 9);
  return std::chrono::duration<double, std::milli>(Steady::now() - t0).count();
}

// `lmcfg fleet backup` of `inventory` into `archive` (the hung line's
// position needs an archived file for a diff or a plan to read the drive).
bool fleet_backup(const std::string& lmcfg, const fs::path& inventory, const fs::path& archive) {
  const pid_t pid = ::fork();
  if (pid == 0) {
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 1);
    ::dup2(devnull, 2);
    const std::string inv = inventory.string(), arc = archive.string();
    ::execl(lmcfg.c_str(), lmcfg.c_str(), "fleet", "backup", inv.c_str(), "--archive", arc.c_str(),
            "--db", LMCFG_DB_PATH, static_cast<char*>(nullptr));
    _exit(127);
  }
  int status = 0;
  ::waitpid(pid, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// The hung line's phase: 12 live diffs and 4 plans of press4/q at once, and
// meanwhile 20 of each of the other clients' requests, timed.
void hung_line_phase(int port) {
  std::vector<std::thread> live;
  std::vector<double> live_ms(16, -1);
  std::vector<int> live_status(16, 0);
  for (int i = 0; i < 16; ++i) {
    live.emplace_back([&, i] {
      live_ms[static_cast<std::size_t>(i)] =
          i % 4 == 3
              ? timed_request(port, "POST", "/api/v1/drives/press4%2Fq/plan",
                              &live_status[static_cast<std::size_t>(i)])
              : timed_request(port, "GET", "/api/v1/drives/press4%2Fq/diff?from=HEAD&to=live",
                              &live_status[static_cast<std::size_t>(i)]);
    });
  }
  std::printf("\na hung line: 12 live diffs and 4 plans of its position at once\n");
  std::printf(
      "| other client's request | n | median ms | max ms | not 200 |\n|---|---|---|---|---|\n");
  for (const char* path : {"/api/v1/drives", "/metrics"}) {
    std::vector<double> ms;
    int bad = 0;
    for (int i = 0; i < 20; ++i) {
      int status = 0;
      ms.push_back(timed_request(port, "GET", path, &status));
      bad += status != 200;
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    std::sort(ms.begin(), ms.end());
    std::printf("| GET %-18s | %d | %9.1f | %6.1f | %7d |\n", path, 20, ms[10], ms.back(), bad);
  }
  for (auto& t : live) t.join();
  std::sort(live_ms.begin(), live_ms.end());
  const auto n503 = std::count(live_status.begin(), live_status.end(), 503);
  std::printf(
      "the 16 live requests: %ld answered 503 line busy, %ld other; answer time median %.1f ms, "
      "max %.1f ms\n",
      static_cast<long>(n503), static_cast<long>(16 - n503), live_ms[8], live_ms.back());
}

}  // namespace

int main(int argc, char** argv) {
  ::signal(SIGPIPE, SIG_IGN);
  const std::string lmcfg = argc > 1 ? argv[1] : LMCFG_BINARY;
  const fs::path dir =
      fs::temp_directory_path() / ("lmcfg-bench-hostile-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string fixture =
      std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json";
  fs::copy_file(fixture, dir / "a.json");
  fs::copy_file(fixture, dir / "c.json");
  // line2's drive never answers (its line timeout 60 s); its position archived
  // first from a simulated drive.
  lmcfg::test::HungLine hung;
  auto plant = [&](const std::string& port2) {
    std::ofstream(dir / "plant.toml")
        << "[[line]]\nname = \"line1\"\nport = \"sim:" + (dir / "a.json").string() +
               "\"\n[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n[[line]]\nname = "
               "\"line2\"\nport = \"" +
               port2 +
               "\"\ntimeout_ms = 60000\nretries = 0\n[[line.drive]]\nname = \"press4/q\"\nid = "
               "0x11\n";
  };
  plant("sim:" + (dir / "c.json").string());
  if (!fleet_backup(lmcfg, dir / "plant.toml", dir / "archive")) {
    std::fprintf(stderr, "lmcfg fleet backup failed\n");
    return 1;
  }
  plant("tcp://127.0.0.1:" + std::to_string(hung.port()));
  int out[2];
  if (::pipe(out) != 0) return 1;
  const pid_t pid = ::fork();
  if (pid == 0) {
    ::dup2(out[1], 1);
    const int devnull = ::open("/dev/null", O_WRONLY);
    ::dup2(devnull, 2);
    const std::string inv = (dir / "plant.toml").string(), arc = (dir / "archive").string();
    ::execl(lmcfg.c_str(), lmcfg.c_str(), "serve", inv.c_str(), "--archive", arc.c_str(),
            "--listen", "127.0.0.1:0", "--db", LMCFG_DB_PATH, static_cast<char*>(nullptr));
    _exit(127);
  }
  ::close(out[1]);
  std::string url;
  char c;
  while (::read(out[0], &c, 1) == 1 && c != '\n') url += c;
  const int port = std::stoi(url.substr(url.rfind(':') + 1));
  std::printf("lmcfg serve %s (pid %d), %s\n\n", lmcfg.c_str(), pid, url.c_str());
  std::this_thread::sleep_for(std::chrono::seconds(2));  // its first backup

  std::printf(
      "| hostile connections                | held | open | median ms | max ms | failed | RSS MB "
      "|\n");
  std::printf("|---|---|---|---|---|---|---|\n");
  const std::vector<const char*> others{"127.0.0.2", "127.0.0.3", "127.0.0.4", "127.0.0.5"};
  for (int n : {0, 50, 200}) {
    Hostile h;
    hold(h, port, n, others);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    table_row("from 4 other addresses", n, port, pid, h);
    h.close_all();
  }
  {
    Hostile h;
    hold(h, port, 200, {"127.0.0.1"});
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
    table_row("from the client's own address", 200, port, pid, h);
    h.close_all();
  }

  std::printf("\nfour 128 MB chunked uploads, no token:\n");
  for (int i = 0; i < 4; ++i) {
    const int fd = connect_from(port, "127.0.0.1");
    const std::string head =
        "POST /api/v1/drives/press3/z/plan HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(port) +
        "\r\nContent-Type: application/json\r\nTransfer-Encoding: chunked\r\n\r\n";
    ::send(fd, head.data(), head.size(), MSG_NOSIGNAL);
    const std::string chunk = "100000\r\n" + std::string(0x100000, 'a') + "\r\n";
    std::size_t sent = 0;
    for (int k = 0; k < 128; ++k) {
      const ssize_t n = ::send(fd, chunk.data(), chunk.size(), MSG_NOSIGNAL);
      if (n <= 0) break;
      sent += static_cast<std::size_t>(n);
    }
    const std::string a = read_all(fd, 2000);
    ::close(fd);
    std::printf("  upload %d: %zu bytes sent before the server closed, answer: %s\n", i + 1, sent,
                a.substr(0, a.find("\r\n")).c_str());
  }
  hung_line_phase(port);
  std::printf("\nservice memory: RSS %.1f MB now, peak (VmHWM) %.1f MB\n",
              static_cast<double>(proc_kb(pid, "VmRSS:")) / 1024.0,
              static_cast<double>(proc_kb(pid, "VmHWM:")) / 1024.0);
  hung.release();
  ::kill(pid, SIGTERM);
  int status = 0;
  ::waitpid(pid, &status, 0);
  fs::remove_all(dir);
  return 0;
}

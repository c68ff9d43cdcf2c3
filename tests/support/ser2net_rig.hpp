#pragma once
// The real ser2net (Debian package ser2net, 4.x) serving a serial device with
// its RFC 2217 accepter on a free 127.0.0.1 port, for the rfc2217 tests and
// bench/bench_rfc2217.cpp. No Catch2 here: the bench uses it too. The process
// is stopped (SIGTERM, waited for) when the rig goes out of scope.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>

#include "files.hpp"
#include "subprocess.hpp"

namespace lmcfg::test {

// The ser2net binary: $LMCFG_SER2NET, else /usr/sbin/ser2net.
inline std::string ser2net_binary() {
  const char* env = std::getenv("LMCFG_SER2NET");
  return env != nullptr && *env != '\0' ? env : "/usr/sbin/ser2net";
}

// Why the ser2net tests cannot run here ("" when they can).
inline std::string ser2net_missing() {
  const std::string bin = ser2net_binary();
  if (::access(bin.c_str(), X_OK) != 0)
    return bin + " is not installed or not executable (Debian package ser2net)";
  return "";
}

// scripts/test.sh sets LMCFG_REQUIRE_SER2NET=1: a missing ser2net fails there.
inline bool ser2net_required() {
  const char* env = std::getenv("LMCFG_REQUIRE_SER2NET");
  return env != nullptr && std::string(env) == "1";
}

// A TCP port on 127.0.0.1 that was free a moment ago (bound to port 0, closed).
inline std::uint16_t free_loopback_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return 0;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  std::uint16_t port = 0;
  if (::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
      ::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0)
    port = ntohs(a.sin_port);
  ::close(fd);
  return port;
}

// True once some process listens on 127.0.0.1:`port` (/proc/net/tcp, state 0A).
// Checked without connecting: a probe connection would make ser2net open the device.
inline bool loopback_listening(std::uint16_t port) {
  std::ifstream in("/proc/net/tcp");
  char want[16];
  std::snprintf(want, sizeof want, "0100007F:%04X", port);
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream f(line);
    std::string slot, local, remote, state;
    f >> slot >> local >> remote >> state;
    if (local == want && state == "0A") return true;
  }
  return false;
}

struct Ser2netRig {
  ScratchDir dir{"ser2net"};
  std::uint16_t port = 0;
  std::unique_ptr<Child> process;
  std::string error;  // why it did not start ("" when it listens)

  // Serves `device` (a pty slave) at `baud`n81 ("local": no modem lines) with
  // a telnet(rfc2217) accepter on 127.0.0.1; waits up to 5 s until it listens.
  // `options`: more lines of the connection's options map ("    chardelay: false\n").
  Ser2netRig(const std::string& device, unsigned baud, const std::string& options = "") {
    port = free_loopback_port();
    if (port == 0) {
      error = "no free loopback port";
      return;
    }
    const auto config = dir.path / "ser2net.yaml";
    spit(config, "%YAML 1.1\n---\nconnection: &line\n  accepter: telnet(rfc2217),tcp,127.0.0.1," +
                     std::to_string(port) + "\n  connector: serialdev," + device + "," +
                     std::to_string(baud) +
                     "n81,local\n  options:\n    kickolduser: true\n    mdns: false\n" + options);
    // exec: the child's pid is ser2net's own, so SIGTERM reaches it. stderr to
    // a log file (ser2net prints "Unable to start mdns" on hosts without avahi).
    process = std::make_unique<Child>(
        std::vector<std::string>{"/bin/sh", "-c",
                                 "exec " + ser2net_binary() + " -n -d -c '" + config.string() +
                                     "' -P '" + (dir.path / "ser2net.pid").string() + "' 2>'" +
                                     (dir.path / "ser2net.log").string() + "'"});
    const auto until = std::chrono::steady_clock::now() + std::chrono::seconds(5);
    while (!loopback_listening(port)) {
      if (std::chrono::steady_clock::now() >= until) {
        error = "ser2net did not listen on 127.0.0.1:" + std::to_string(port) +
                " within 5 s; its log: " + slurp(dir.path / "ser2net.log");
        return;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  }
  ~Ser2netRig() { process.reset(); }  // before the scratch directory goes
  Ser2netRig(const Ser2netRig&) = delete;
  Ser2netRig& operator=(const Ser2netRig&) = delete;
  bool ok() const { return error.empty(); }
};

}  // namespace lmcfg::test

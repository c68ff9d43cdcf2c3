// TCP transport against listening sockets on the loopback interface only.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cstring>
#include <thread>
#include <vector>

#include "transport/pty.hpp"
#include "transport/transport.hpp"
#include "transport_test_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_tcp {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;

namespace {

// A socket bound to the loopback address on an ephemeral port; listening unless told not to.
struct Listener {
  UniqueFd fd;
  std::uint16_t port = 0;
};

Listener make_listener(int family, bool listening, int backlog = 4) {
  Listener l;
  l.fd.reset(::socket(family, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!l.fd) return l;
  sockaddr_storage ss{};
  socklen_t len = 0;
  if (family == AF_INET) {
    auto* a = reinterpret_cast<sockaddr_in*>(&ss);
    a->sin_family = AF_INET;
    a->sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    len = sizeof(sockaddr_in);
  } else {
    auto* a = reinterpret_cast<sockaddr_in6*>(&ss);
    a->sin6_family = AF_INET6;
    a->sin6_addr = in6addr_loopback;
    len = sizeof(sockaddr_in6);
  }
  if (::bind(l.fd.get(), reinterpret_cast<sockaddr*>(&ss), len) != 0 ||
      (listening && ::listen(l.fd.get(), backlog) != 0)) {
    l.fd.reset();
    return l;
  }
  socklen_t got = sizeof ss;
  ::getsockname(l.fd.get(), reinterpret_cast<sockaddr*>(&ss), &got);
  l.port = family == AF_INET ? ntohs(reinterpret_cast<sockaddr_in*>(&ss)->sin_port)
                             : ntohs(reinterpret_cast<sockaddr_in6*>(&ss)->sin6_port);
  return l;
}

// Accepts one connection within 3 s; invalid fd otherwise.
UniqueFd accept_one(const Listener& l) {
  pollfd pfd{l.fd.get(), POLLIN, 0};
  if (::poll(&pfd, 1, 3000) != 1) return UniqueFd();
  return UniqueFd(::accept4(l.fd.get(), nullptr, nullptr, SOCK_CLOEXEC));
}

// Echoes everything back until the client closes or 3 s pass without data.
void echo_server(const Listener* l) {
  UniqueFd c = accept_one(*l);
  if (!c) return;
  std::uint8_t buf[1024];
  for (int i = 0; i < 1000; ++i) {
    pollfd pfd{c.get(), POLLIN, 0};
    if (::poll(&pfd, 1, 3000) != 1) return;
    const ssize_t n = ::recv(c.get(), buf, sizeof buf, 0);
    if (n <= 0) return;
    if (::send(c.get(), buf, static_cast<std::size_t>(n), MSG_NOSIGNAL) != n) return;
  }
}

using test::read_n;

}  // namespace

TEST_CASE("tcp echoes bytes over IPv4 loopback", "[transport]") {
  Listener l = make_listener(AF_INET, true);
  REQUIRE(l.fd.valid());
  std::thread server(echo_server, &l);
  {
    auto t = open_tcp("127.0.0.1", l.port, 2000ms);
    REQUIRE(t.ok());
    CHECK((*t)->describe() == "tcp 127.0.0.1:" + std::to_string(l.port));
    CHECK((*t)->byte_time_us() == 0.0);
    Bytes payload;
    for (unsigned i = 0; i < 600; ++i) payload.push_back(static_cast<std::uint8_t>(i * 7));
    REQUIRE((*t)->write(payload).ok());
    CHECK(read_n(**t, payload.size()) == payload);

    auto idle = (*t)->read_some(100ms);
    REQUIRE(idle.ok());
    CHECK(idle->empty());
  }
  server.join();
}

TEST_CASE("tcp echoes bytes over IPv6 loopback", "[transport]") {
  Listener l = make_listener(AF_INET6, true);
  if (!l.fd.valid()) {
    WARN("no IPv6 loopback here; skipped");
    return;
  }
  std::thread server(echo_server, &l);
  {
    auto t = open_tcp("::1", l.port, 2000ms);
    REQUIRE(t.ok());
    CHECK((*t)->describe() == "tcp [::1]:" + std::to_string(l.port));
    REQUIRE((*t)->write(Bytes{0x01, 0x11, 0x05, 0x02, 0x00, 0x03, 0x04}).ok());
    CHECK(read_n(**t, 7) == Bytes{0x01, 0x11, 0x05, 0x02, 0x00, 0x03, 0x04});
  }
  server.join();
  auto bracketed = open_tcp("[::1]", l.port, 500ms);  // nobody accepts, the kernel still connects
  if (bracketed.ok()) CHECK((*bracketed)->describe() == "tcp [::1]:" + std::to_string(l.port));
}

TEST_CASE("tcp connect refused names host and port", "[transport]") {
  Listener l = make_listener(AF_INET, false);  // bound, not listening: the SYN gets a reset
  REQUIRE(l.fd.valid());
  const auto t0 = Clock::now();
  auto t = open_tcp("127.0.0.1", l.port, 2000ms);
  CHECK(Clock::now() - t0 < 1500ms);
  REQUIRE_FALSE(t.ok());
  CHECK(t.error().code == Errc::io_error);
  CHECK(t.error().message ==
        "tcp 127.0.0.1:" + std::to_string(l.port) + ": cannot connect: Connection refused");
}

TEST_CASE("tcp rejects port 0 and an empty host", "[transport]") {
  auto p = open_tcp("127.0.0.1", 0, 100ms);
  REQUIRE_FALSE(p.ok());
  CHECK(p.error().code == Errc::invalid_argument);
  CHECK(p.error().message == "tcp 127.0.0.1:0: port 0 is not a valid port");
  auto h = open_tcp("", 4001, 100ms);
  REQUIRE_FALSE(h.ok());
  CHECK(h.error().message == "tcp: host is empty");
}

TEST_CASE("tcp peer close gives link_closed", "[transport]") {
  Listener l = make_listener(AF_INET, true);
  REQUIRE(l.fd.valid());
  std::thread server([&l] {
    UniqueFd c = accept_one(l);
    const std::uint8_t hello[] = {0xAA, 0xBB};
    if (c) ::send(c.get(), hello, sizeof hello, MSG_NOSIGNAL);
  });  // closes the connection on return
  auto t = open_tcp("127.0.0.1", l.port, 2000ms);
  REQUIRE(t.ok());
  server.join();
  const std::string where = "tcp 127.0.0.1:" + std::to_string(l.port);

  CHECK(read_n(**t, 2) == Bytes{0xAA, 0xBB});  // data sent before the close still arrives
  const auto t0 = Clock::now();
  auto r = (*t)->read_some(3000ms);
  CHECK(Clock::now() - t0 < 1500ms);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::link_closed);
  CHECK(r.error().message == where + ": peer closed the connection");

  // Writing to the closed peer fails (EPIPE / ECONNRESET) instead of raising SIGPIPE.
  bool failed = false;
  for (int i = 0; i < 50 && !failed; ++i) {
    auto w = (*t)->write(Bytes{0x01, 0x02, 0x03});
    if (!w.ok()) {
      failed = true;
      CHECK(w.error().code == Errc::link_closed);
      CHECK(w.error().message.rfind(where + ": write failed: ", 0) == 0);
    } else {
      std::this_thread::sleep_for(10ms);
    }
  }
  CHECK(failed);
}

TEST_CASE("tcp discard_input drops received bytes", "[transport]") {
  Listener l = make_listener(AF_INET, true);
  REQUIRE(l.fd.valid());
  std::thread server(echo_server, &l);
  {
    auto t = open_tcp("127.0.0.1", l.port, 2000ms);
    REQUIRE(t.ok());
    REQUIRE((*t)->write(Bytes(100, 0x42)).ok());
    std::this_thread::sleep_for(100ms);  // let the echo come back
    (*t)->discard_input();
    auto r = (*t)->read_some(100ms);
    REQUIRE(r.ok());
    CHECK(r->empty());
  }
  server.join();
}

TEST_CASE("tcp connect gives up at the deadline", "[transport]") {
  // A listener that never accepts, with its queue filled: Linux drops further SYNs.
  Listener l = make_listener(AF_INET, true, 0);
  REQUIRE(l.fd.valid());
  std::vector<UniqueFd> fillers;
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  a.sin_port = htons(l.port);
  for (int i = 0; i < 4; ++i) {
    UniqueFd f(::socket(AF_INET, SOCK_STREAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0));
    ::connect(f.get(), reinterpret_cast<sockaddr*>(&a), sizeof a);
    fillers.push_back(std::move(f));
  }
  std::this_thread::sleep_for(50ms);
  const auto t0 = Clock::now();
  auto t = open_tcp("127.0.0.1", l.port, 300ms);
  const auto elapsed = Clock::now() - t0;
  if (t.ok()) {
    WARN("this kernel accepted the connection despite a full backlog; deadline not exercised");
    return;
  }
  CHECK(t.error().code == Errc::timeout);
  CHECK(t.error().message ==
        "tcp 127.0.0.1:" + std::to_string(l.port) + ": connect timed out after 300 ms");
  CHECK(elapsed >= 290ms);
  CHECK(elapsed < 2000ms);
}

}  // namespace transport_test_tcp

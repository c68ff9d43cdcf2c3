// The HTTP server's sockets (web_socket.cpp: POSIX poll and a pipe;
// web_socket_win32.cpp: WSAPoll and a loopback datagram pair), through a
// real TCP client.
#include <catch2/catch.hpp>
#include <chrono>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "raw_http.hpp"
#include "web/web_socket.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace web_test_web_socket {

using namespace lmcfg;
using namespace lmcfg::web;
using lmcfg::test::RawClient;

namespace {
// The next connection on `listener`, waiting for it up to 5 s.
int accept_within(int listener, std::string& peer) {
  for (int i = 0; i < 50; ++i) {
    std::vector<Watch> w{{listener, true, false}};
    REQUIRE(wait_sockets(w, 100));
    if (w[0].readable) return accept_one(listener, peer);
  }
  return -1;
}
}  // namespace

TEST_CASE("web socket: a listener on any free port, its port not shared with a second",
          "[web][web_socket]") {
  auto a = listen_on("127.0.0.1", 0);
  REQUIRE(a.ok());
  CHECK(a->port > 0);
  auto b = listen_on("127.0.0.1", a->port);
  REQUIRE_FALSE(b.ok());
  CHECK(b.error().code == Errc::io_error);
  CHECK(b.error().message == "cannot listen on 127.0.0.1:" + std::to_string(a->port) +
                                 " (address in use or not on this host)");
  auto c = listen_on("192.0.2.1", 0);  // TEST-NET-1: not an address of this host
  REQUIRE_FALSE(c.ok());
  CHECK(c.error().message == "cannot listen on 192.0.2.1:0 (address in use or not on this host)");
  std::string peer;
  CHECK(accept_one(a->socket, peer) == -1);  // nobody waiting: never blocks
  close_socket(a->socket);
}

TEST_CASE("web socket: accepted connections name their peer, bytes both ways, the peer's close",
          "[web][web_socket]") {
  auto l = listen_on("127.0.0.1", 0);
  REQUIRE(l.ok());
  std::optional<RawClient> client;
  client.emplace(l->port, "127.0.0.2");
  REQUIRE(client->connected());
  std::string peer;
  const int s = accept_within(l->socket, peer);
  REQUIRE(s != -1);
  CHECK(peer == "127.0.0.2");

  char buf[64];
  IoStep r = recv_some(s, buf, sizeof buf);  // nothing sent yet: try again later
  CHECK(r.want_read);
  CHECK(r.n == 0);
  CHECK_FALSE(r.closed);

  REQUIRE(client->send("GET / HTTP/1.1\r\n"));
  std::string got;
  for (int i = 0; i < 50 && got.size() < 16; ++i) {
    std::vector<Watch> w{{s, true, false}};
    REQUIRE(wait_sockets(w, 100));
    if (!w[0].readable) continue;
    r = recv_some(s, buf, sizeof buf);
    got.append(buf, r.n);
  }
  CHECK(got == "GET / HTTP/1.1\r\n");

  const std::string answer = "HTTP/1.1 204 No Content\r\n\r\n";
  r = send_some(s, answer.data(), answer.size());
  CHECK(r.n == answer.size());
  CHECK(client->read(2000, "\r\n\r\n") == answer);

  client.reset();
  bool closed = false;
  for (int i = 0; i < 50 && !closed; ++i) {
    std::vector<Watch> w{{s, true, false}};
    REQUIRE(wait_sockets(w, 100));
    if (!w[0].readable && !w[0].hangup) continue;
    r = recv_some(s, buf, sizeof buf);
    closed = r.closed;
  }
  CHECK(closed);
  CHECK(r.error.empty());  // an orderly close
  close_socket(s);
  close_socket(l->socket);
}

TEST_CASE("web socket: the waker ends a wait from another thread, drained it is quiet again",
          "[web][web_socket]") {
  Waker waker;
  REQUIRE(waker.open().ok());
  std::vector<Watch> w{{waker.socket(), true, false}};
  REQUIRE(wait_sockets(w, 0));
  CHECK_FALSE(w[0].readable);

  const auto t0 = std::chrono::steady_clock::now();
  std::thread poker([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    waker.poke();
    waker.poke();
  });
  REQUIRE(wait_sockets(w, 5000));
  poker.join();
  CHECK(w[0].readable);
  CHECK(std::chrono::steady_clock::now() - t0 < std::chrono::seconds(4));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));  // the second poke's byte too
  waker.drain();
  REQUIRE(wait_sockets(w, 0));
  CHECK_FALSE(w[0].readable);
}

TEST_CASE("web socket: loopback addresses are 127.0.0.0/8 and ::1, written as numbers",
          "[web][web_socket]") {
  for (const char* yes : {"127.0.0.1", "127.255.0.9", "::1", "0:0:0:0:0:0:0:1"})
    CHECK(is_loopback_address(yes));
  for (const char* no : {"10.0.0.1", "0.0.0.0", "::", "::2", "localhost", "127.example.com",
                         "128.0.0.1", "", "127.0.0.1 "})
    CHECK_FALSE(is_loopback_address(no));
}

}  // namespace web_test_web_socket

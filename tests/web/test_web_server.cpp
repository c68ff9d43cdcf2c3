// lmcfg serve's HTTP server (lib/web/web_server.cpp) over real sockets on
// 127.0.0.1: slow, idle and silent clients, connection limits with eviction,
// refusals on the wire, a handler's exception, 100-continue, pipelining, stop.
// Timeouts are shortened so that the tests take well under a second each.
#include <atomic>
#include <catch2/catch.hpp>
#include <condition_variable>
#include <mutex>
#include <thread>

#include "raw_http.hpp"
#include "web/web_server.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace web_test_web_server {

using namespace lmcfg;
using namespace lmcfg::web;
using lmcfg::test::RawClient;
using namespace std::chrono_literals;

namespace {

struct TestServer {
  std::unique_ptr<Server> server;
  std::thread thread;
  int port = 0;
  std::mutex mu;
  std::vector<std::string> log;

  explicit TestServer(ServerOptions o) {
    if (!o.handle)
      o.handle = [](Request& req, Response& res) {
        res.set_content("path " + req.path + " body " + req.body + "\n", "text/plain");
      };
    o.log = [this](const std::string& s) {
      std::lock_guard<std::mutex> lock(mu);
      log.push_back(s);
    };
    server = std::make_unique<Server>(std::move(o));
    auto p = server->bind("127.0.0.1", 0);
    REQUIRE(p.ok());
    port = *p;
    thread = std::thread([this] { server->serve(); });
  }
  ~TestServer() {
    server->stop();
    thread.join();
  }
  std::string get(const std::string& path, const char* from = nullptr) {
    RawClient c(port, from);
    c.send("GET " + path + " HTTP/1.1\r\nHost: h\r\nConnection: close\r\n\r\n");
    return c.response(2000);
  }
};

ServerOptions quick() {
  ServerOptions o;
  o.head_timeout = 300ms;
  o.body_timeout = 300ms;
  o.idle_timeout = 200ms;
  return o;
}

bool starts_with(const std::string& s, const std::string& p) { return s.rfind(p, 0) == 0; }

}  // namespace

TEST_CASE("web server: a slow client gets 408 and is closed, others are answered meanwhile",
          "[web][web_server]") {
  TestServer s(quick());
  RawClient slow(s.port);
  REQUIRE(slow.send("GET /a HTTP/1.1\r\nHo"));
  const auto t0 = std::chrono::steady_clock::now();
  CHECK(starts_with(s.get("/b"), "HTTP/1.1 200 OK\r\n"));
  CHECK(std::chrono::steady_clock::now() - t0 < 250ms);
  const std::string answer = slow.read(3000);
  CHECK(starts_with(answer, "HTTP/1.1 408 Request Timeout\r\n"));
  CHECK(answer.find("Connection: close\r\n") != std::string::npos);
  CHECK(answer.find("the request's head did not arrive within 300 ms") != std::string::npos);
  CHECK(slow.closed(1000));
  CHECK(s.server->stats().timed_out == 1);

  // The body too: a head that announces 10 bytes and sends 2.
  RawClient body(s.port);
  REQUIRE(body.send("POST /a HTTP/1.1\r\nHost: h\r\nContent-Length: 10\r\n\r\nab"));
  CHECK(body.read(3000).find("the request's body did not arrive within 300 ms") !=
        std::string::npos);
  CHECK(body.closed(1000));
}

TEST_CASE("web server: idle and silent connections are closed without an answer",
          "[web][web_server]") {
  TestServer s(quick());
  RawClient idle(s.port);
  REQUIRE(idle.send("GET /a HTTP/1.1\r\nHost: h\r\n\r\n"));
  CHECK(starts_with(idle.response(1000), "HTTP/1.1 200 OK\r\n"));
  // Keep-alive: the next request on the same connection is served ...
  REQUIRE(idle.send("GET /b HTTP/1.1\r\nHost: h\r\n\r\n"));
  CHECK(idle.response(1000).find("path /b") != std::string::npos);
  // ... and after idle_timeout without one, the connection is closed, nothing sent.
  CHECK(idle.read(2000).empty());
  CHECK(idle.closed(10));
  RawClient silent(s.port);
  CHECK(silent.read(2000).empty());
  CHECK(silent.closed(10));
}

TEST_CASE("web server: over the per-address limit the oldest waiting connection makes room",
          "[web][web_server]") {
  ServerOptions o = quick();
  o.head_timeout = 5s;
  o.idle_timeout = 5s;
  o.max_per_address = 4;
  o.max_connections = 6;
  TestServer s(o);
  std::vector<RawClient> held;
  for (int i = 0; i < 4; ++i) {
    held.emplace_back(s.port);
    REQUIRE(held.back().send("GET /held HTTP/1.1\r\n"));  // never finished
    std::this_thread::sleep_for(20ms);
  }
  // The legitimate client from the same address is answered at once ...
  CHECK(starts_with(s.get("/legit"), "HTTP/1.1 200 OK\r\n"));
  // ... and the oldest held connection went for it, the others stay.
  CHECK(held[0].closed(500));
  CHECK_FALSE(held[1].closed(50));
  CHECK(s.server->stats().evicted == 1);
  // Other addresses have their own count; the total limit evicts from anyone.
  RawClient other1(s.port, "127.0.0.2"), other2(s.port, "127.0.0.2"), other3(s.port, "127.0.0.2");
  for (RawClient* other : {&other1, &other2, &other3}) other->send("GET /x HTTP/1.1\r\n");
  std::this_thread::sleep_for(50ms);
  CHECK(starts_with(s.get("/legit2", "127.0.0.3"), "HTTP/1.1 200 OK\r\n"));
  CHECK(s.server->stats().evicted == 2);
  CHECK(held[1].closed(500));  // the oldest of all
}

TEST_CASE("web server: connections that announce a body and never send it make room too",
          "[web][web_server]") {
  // The shape of the attack: every slot held by a complete head with
  // Content-Length: 4096 and no body, from several addresses, each at its
  // per-address limit; legitimate GETs from another address still answered.
  ServerOptions o = quick();
  o.head_timeout = 5s;
  o.body_timeout = 5s;
  o.idle_timeout = 5s;
  o.max_per_address = 4;
  o.max_connections = 8;
  TestServer s(o);
  std::vector<RawClient> held;
  for (const char* from : {"127.0.0.2", "127.0.0.3", "127.0.0.4"}) {
    for (int i = 0; i < 4; ++i) {
      held.emplace_back(s.port, from);
      REQUIRE(held.back().send("POST /held HTTP/1.1\r\nHost: h\r\nContent-Length: 4096\r\n\r\n"));
      std::this_thread::sleep_for(10ms);
    }
  }
  std::this_thread::sleep_for(50ms);
  // 12 sent, 8 fit: the 4 oldest, from the addresses with the most, went.
  CHECK(s.server->stats().evicted == 4);
  CHECK(s.server->stats().open == 8);
  CHECK(held[0].closed(500));
  CHECK_FALSE(held.back().closed(50));
  for (int i = 0; i < 10; ++i)
    CHECK(starts_with(s.get("/legit", "127.0.0.9"), "HTTP/1.1 200 OK\r\n"));
  CHECK(s.server->stats().refused == 0);
  // The first GET made room (one held connection of 127.0.0.4, which had the
  // most); each answered GET closed its own, so the next ones found room.
  CHECK(s.server->stats().evicted == 5);
  CHECK_FALSE(held.back().closed(50));
  // A client with one connection keeps it: its idle connection is not the
  // one to go while others hold more.
  RawClient few(s.port, "127.0.0.9");
  REQUIRE(few.send("GET /few HTTP/1.1\r\nHost: h\r\n\r\n"));
  CHECK(few.response(1000).find("path /few") != std::string::npos);  // now idle, kept alive
  std::vector<RawClient> more;
  for (int i = 0; i < 3; ++i) {
    more.emplace_back(s.port, "127.0.0.2");
    REQUIRE(more.back().send("POST /held HTTP/1.1\r\nHost: h\r\nContent-Length: 4096\r\n\r\n"));
    std::this_thread::sleep_for(20ms);
  }
  CHECK(s.server->stats().evicted == 8);
  REQUIRE(few.send("GET /again HTTP/1.1\r\nHost: h\r\n\r\n"));
  CHECK(few.response(1000).find("path /again") != std::string::npos);
}

TEST_CASE("web server: when every connection has a request in progress, a new one gets 503",
          "[web][web_server]") {
  std::mutex mu;
  std::condition_variable cv;
  bool release = false;
  std::atomic<int> inside{0};
  ServerOptions o = quick();
  o.max_connections = 2;
  o.handle = [&](Request&, Response& res) {
    ++inside;
    std::unique_lock<std::mutex> lock(mu);
    cv.wait(lock, [&] { return release; });
    res.set_content("done\n", "text/plain");
  };
  TestServer s(o);
  RawClient a(s.port), b(s.port);
  a.send("GET /a HTTP/1.1\r\nHost: h\r\n\r\n");
  b.send("GET /b HTTP/1.1\r\nHost: h\r\n\r\n");
  for (int i = 0; i < 200 && inside < 2; ++i) std::this_thread::sleep_for(5ms);
  REQUIRE(inside == 2);
  RawClient c(s.port);
  const std::string refused = c.read(1000);
  CHECK(starts_with(refused, "HTTP/1.1 503 Service Unavailable\r\n"));
  CHECK(refused.find("too many connections: 2 open in all; try again later") != std::string::npos);
  CHECK(refused.find("Retry-After: 1\r\n") != std::string::npos);
  CHECK(s.server->stats().refused == 1);
  {
    std::lock_guard<std::mutex> lock(mu);
    release = true;
  }
  cv.notify_all();
  CHECK(a.response(1000).find("done") != std::string::npos);
  CHECK(b.response(1000).find("done") != std::string::npos);
}

TEST_CASE("web server: refusals go on the wire with their status, and the connection closes",
          "[web][web_server]") {
  TestServer s(quick());
  RawClient big(s.port);
  big.send("POST /x HTTP/1.1\r\nHost: h\r\nTransfer-Encoding: chunked\r\n\r\n8000000\r\n");
  const std::string a = big.read(1000);
  CHECK(starts_with(a, "HTTP/1.1 413 Content Too Large\r\n"));
  CHECK(a.find("the request body is larger than the 4096 bytes this service accepts") !=
        std::string::npos);
  CHECK(big.closed(500));
  RawClient bad(s.port);
  bad.send("GET /%FF HTTP/1.1\r\nHost: h\r\n\r\n");
  CHECK(starts_with(bad.read(1000), "HTTP/1.1 400 Bad Request\r\n"));
  CHECK(bad.closed(500));
  std::lock_guard<std::mutex> lock(s.mu);
  CHECK(std::find(s.log.begin(), s.log.end(),
                  "http 127.0.0.1 refused: 400 the request path '/%FF' is not valid UTF-8 once "
                  "decoded (byte 1)") != s.log.end());
}

TEST_CASE("web server: a handler's exception is a 500 and the server goes on",
          "[web][web_server]") {
  ServerOptions o = quick();
  o.handle = [](Request& req, Response& res) {
    if (req.path == "/throw") throw std::runtime_error("boom\n\xFF");
    res.set_content("fine\n", "text/plain");
  };
  TestServer s(o);
  const std::string a = s.get("/throw");
  CHECK(starts_with(a, "HTTP/1.1 500 Internal Server Error\r\n"));
  CHECK(a.find("internal error while answering this request; the service goes on") !=
        std::string::npos);
  CHECK(s.get("/ok").find("fine") != std::string::npos);
  CHECK(s.server->stats().handler_errors == 1);
  std::lock_guard<std::mutex> lock(s.mu);
  CHECK(std::find(s.log.begin(), s.log.end(),
                  "http 127.0.0.1 GET /throw: internal error: boom\\x0A\\xFF") != s.log.end());
}

TEST_CASE("web server: 100-continue, pipelining, HEAD, HTTP/1.0", "[web][web_server]") {
  TestServer s(quick());
  RawClient c(s.port);
  c.send("POST /p HTTP/1.1\r\nHost: h\r\nContent-Length: 3\r\nExpect: 100-continue\r\n\r\n");
  CHECK(c.read(1000, "\r\n\r\n") == "HTTP/1.1 100 Continue\r\n\r\n");
  c.send("abc");
  CHECK(c.response(1000).find("path /p body abc") != std::string::npos);
  c.send("GET /1 HTTP/1.1\r\nHost: h\r\n\r\nGET /2 HTTP/1.1\r\nHost: h\r\n\r\n");
  std::string both = c.read(1000, "path /2");
  CHECK(both.find("path /1") < both.find("path /2"));
  c.send("HEAD /3 HTTP/1.1\r\nHost: h\r\n\r\n");
  const std::string head = c.read(1000, "\r\n\r\n");
  CHECK(head.find("Content-Length: 14\r\n") != std::string::npos);
  CHECK(head.substr(head.size() - 4) == "\r\n\r\n");
  RawClient old(s.port);
  old.send("GET /4 HTTP/1.0\r\n\r\n");
  CHECK(old.read(1000).find("Connection: close\r\n") != std::string::npos);
  CHECK(old.closed(500));
}

TEST_CASE("web server: stop before serve, and stop with connections open", "[web][web_server]") {
  Server early(quick());
  REQUIRE(early.bind("127.0.0.1", 0).ok());
  early.stop();
  early.serve();  // returns at once
  auto s = std::make_unique<TestServer>(quick());
  RawClient held(s->port);
  held.send("GET /x HTTP/1.1\r\n");
  s.reset();  // stop and join with a connection open
  CHECK(held.closed(500));
}

TEST_CASE("web server: a port in use is refused with the address", "[web][web_server]") {
  TestServer s(quick());
  Server second(quick());
  auto r = second.bind("127.0.0.1", s.port);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message == "cannot listen on 127.0.0.1:" + std::to_string(s.port) +
                                 " (address in use or not on this host)");
}

}  // namespace web_test_web_server

// Event delivery of lmcfg serve (lib/serve/notify.cpp): the notify command
// run without a shell with the event on stdin, webhooks POSTed to a real
// cpp-httplib receiver on 127.0.0.1, retries with back-off, the exact log
// lines, and what the Notifier does when it is destroyed.
#include <arpa/inet.h>
#include <httplib.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>

#include "files.hpp"
#include "serve/notify.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_notify {

using namespace lmcfg;
using namespace lmcfg::test;
namespace fs = std::filesystem;
using namespace std::chrono_literals;

namespace {

// A webhook receiver on 127.0.0.1: every POST kept (path, content type,
// body); it answers with the statuses of `answers` in turn, then 204.
struct Receiver {
  httplib::Server server;
  std::thread thread;
  int port = 0;
  std::mutex mu;
  struct Post {
    std::string path, content_type, body;
  };
  std::vector<Post> posts;
  std::vector<int> answers;

  explicit Receiver(std::vector<int> statuses = {}) : answers(std::move(statuses)) {
    server.Post(".*", [this](const httplib::Request& req, httplib::Response& res) {
      std::lock_guard<std::mutex> lock(mu);
      posts.push_back({req.target, req.get_header_value("Content-Type"), req.body});
      const std::size_t n = posts.size() - 1;
      res.status = n < answers.size() ? answers[n] : 204;
    });
    port = server.bind_to_any_port("127.0.0.1");
    REQUIRE(port > 0);
    thread = std::thread([this] { server.listen_after_bind(); });
  }
  ~Receiver() {
    server.stop();
    thread.join();
  }
  std::string url(const std::string& path = "/hook") const {
    return "http://127.0.0.1:" + std::to_string(port) + path;
  }
  std::vector<Post> got() {
    std::lock_guard<std::mutex> lock(mu);
    return posts;
  }
};

// A port on 127.0.0.1 nobody listens on: bound by the system, then closed.
int closed_port() {
  const int fd = ::socket(AF_INET, SOCK_STREAM, 0);
  REQUIRE(fd >= 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  REQUIRE(::bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0);
  socklen_t len = sizeof a;
  REQUIRE(::getsockname(fd, reinterpret_cast<sockaddr*>(&a), &len) == 0);
  ::close(fd);
  return ntohs(a.sin_port);
}

// The log lines a Notifier writes, safe to read while its thread writes.
struct Log {
  std::mutex mu;
  std::vector<std::string> lines;
  std::function<void(const std::string&)> sink() {
    return [this](const std::string& s) {
      std::lock_guard<std::mutex> lock(mu);
      lines.push_back(s);
    };
  }
  std::vector<std::string> get() {
    std::lock_guard<std::mutex> lock(mu);
    return lines;
  }
};

}  // namespace

TEST_CASE("serve: a webhook receives the event JSON, a dead one is retried, then given up",
          "[serve][notify]") {
  httplib::Server receiver;
  std::mutex mu;
  std::vector<nlohmann::json> got;
  receiver.Post("/hook", [&](const httplib::Request& req, httplib::Response& res) {
    std::lock_guard<std::mutex> lock(mu);
    got.push_back(nlohmann::json::parse(req.body));
    res.status = 204;
  });
  const int port = receiver.bind_to_any_port("127.0.0.1");
  REQUIRE(port > 0);
  std::thread t([&] { receiver.listen_after_bind(); });

  {
    Rig rig;
    serve::NotifyOptions no;
    no.webhook = "http://127.0.0.1:" + std::to_string(port) + "/hook";
    std::vector<std::string> log;
    no.log = [&](const std::string& s) { log.push_back(s); };
    serve::Notifier notifier(no);
    rig.at(rig.now);
    // The service's events go to the notifier as the tool wires them.
    write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
    rig.at(rig.now + 15min);
    for (auto& e : rig.take_events()) notifier.send(e.dump());
    notifier.flush();
    CHECK(log.empty());
  }
  {
    std::lock_guard<std::mutex> lock(mu);
    REQUIRE(got.size() == 1);
    CHECK(got[0]["event"] == "drift");
    CHECK(got[0]["drive"] == "press3/x");
    CHECK(got[0]["upids"][0]["upid"] == "0010h");
  }
  receiver.stop();
  t.join();

  // Nobody listening any more: three attempts (10 ms, 20 ms apart), then given up and logged.
  serve::NotifyOptions dead;
  dead.webhook = "http://127.0.0.1:" + std::to_string(port) + "/hook";
  dead.attempts = 3;
  dead.backoff_ms = 10;
  std::vector<std::string> log;
  dead.log = [&](const std::string& s) { log.push_back(s); };
  serve::Notifier notifier(dead);
  notifier.send(R"({"event":"drift"})");
  notifier.flush();
  REQUIRE(log.size() == 3);
  CHECK(log[0].find("; attempt 1 of 3, next in 10 ms") != std::string::npos);
  CHECK(log[1].find("; attempt 2 of 3, next in 20 ms") != std::string::npos);
  CHECK(log[2].find("; gave up after 3 attempt(s), event dropped: {\"event\":\"drift\"}") !=
        std::string::npos);
}

TEST_CASE("notify: post_json sends the JSON as application/json to the URL's path",
          "[serve][notify]") {
  Receiver rx({500});
  auto r = serve::post_json(rx.url("/hooks/lmcfg?team=plant"), R"({"event":"drift"})");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "webhook " + rx.url("/hooks/lmcfg?team=plant") + ": HTTP 500");
  REQUIRE(serve::post_json(rx.url("/hooks/lmcfg?team=plant"), R"({"event":"drift"})").ok());
  // A URL without a path posts to "/".
  REQUIRE(serve::post_json("http://127.0.0.1:" + std::to_string(rx.port), "{}").ok());
  const auto got = rx.got();
  REQUIRE(got.size() == 3);
  CHECK(got[1].path == "/hooks/lmcfg?team=plant");
  CHECK(got[1].content_type == "application/json");
  CHECK(got[1].body == R"({"event":"drift"})");
  CHECK(got[2].path == "/");
  CHECK(got[2].body == "{}");

  const std::string dead = "http://127.0.0.1:" + std::to_string(closed_port()) + "/hook";
  r = serve::post_json(dead, "{}");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::io_error);
  CHECK(r.error().message == "webhook " + dead + ": Connection");
}

TEST_CASE("notify: the command first, then the webhook, events in the order sent",
          "[serve][notify]") {
  ScratchDir d("notify-order");
  Receiver rx;
  const std::string out = (d.path / "events.txt").string();
  serve::NotifyOptions o;
  o.command = shell_script(d.path, "append.sh", "cat >> '" + out + "'\n").string();
  o.webhook = rx.url();
  Log log;
  o.log = log.sink();
  {
    serve::Notifier n(o);
    n.send(R"({"n":1})");
    n.send(R"({"n":2})");
    n.send(R"({"n":3})");
    n.flush();
    // Each event is on the command's stdin as one line.
    CHECK(slurp(out) == "{\"n\":1}\n{\"n\":2}\n{\"n\":3}\n");
    const auto got = rx.got();
    REQUIRE(got.size() == 3);
    CHECK(got[0].body == R"({"n":1})");
    CHECK(got[1].body == R"({"n":2})");
    CHECK(got[2].body == R"({"n":3})");
  }
  CHECK(log.get().empty());

  // A failing command is logged, and the webhook still gets the event.
  o.command = shell_script(d.path, "fail.sh", "exit 2\n").string();
  {
    serve::Notifier n(o);
    n.send(R"({"n":4})");
    n.flush();
  }
  REQUIRE(log.get() ==
          std::vector<std::string>{"notify command " + o.command + " failed (exit 2)"});
  CHECK(rx.got().back().body == R"({"n":4})");
}

TEST_CASE("notify: a webhook that fails twice gets the event on the third try, back-off doubled",
          "[serve][notify]") {
  Receiver rx({503, 500});
  serve::NotifyOptions o;
  o.webhook = rx.url();
  o.attempts = 3;
  o.backoff_ms = 20;
  Log log;
  o.log = log.sink();
  const auto t0 = std::chrono::steady_clock::now();
  {
    serve::Notifier n(o);
    n.send(R"({"event":"failed"})");
    n.flush();
  }
  // 20 ms after the first failure, 40 ms after the second.
  CHECK(std::chrono::steady_clock::now() - t0 >= 60ms);
  CHECK(log.get() == std::vector<std::string>{
                         "webhook " + rx.url() + ": HTTP 503; attempt 1 of 3, next in 20 ms",
                         "webhook " + rx.url() + ": HTTP 500; attempt 2 of 3, next in 40 ms"});
  const auto got = rx.got();
  REQUIRE(got.size() == 3);
  for (const auto& p : got) CHECK(p.body == R"({"event":"failed"})");
}

TEST_CASE("notify: one attempt only gives up at once, the next event is still delivered",
          "[serve][notify]") {
  Receiver rx({500});
  serve::NotifyOptions o;
  o.webhook = rx.url();
  o.attempts = 1;
  o.backoff_ms = 60000;
  Log log;
  o.log = log.sink();
  {
    serve::Notifier n(o);
    n.send(R"({"n":1})");
    n.send(R"({"n":2})");
    n.flush();
  }
  CHECK(log.get() == std::vector<std::string>{"webhook " + rx.url() +
                                              ": HTTP 500; gave up after 1 attempt(s), event "
                                              "dropped: {\"n\":1}"});
  const auto got = rx.got();
  REQUIRE(got.size() == 2);
  CHECK(got[1].body == R"({"n":2})");
}

TEST_CASE("notify: destroyed, the Notifier delivers what is queued and cuts a back-off short",
          "[serve][notify]") {
  SECTION("queued events to a live receiver are all delivered") {
    Receiver rx;
    serve::NotifyOptions o;
    o.webhook = rx.url();
    {
      serve::Notifier n(o);
      for (int i = 0; i < 5; ++i) n.send("{\"n\":" + std::to_string(i) + "}");
    }  // no flush: the destructor delivers
    const auto got = rx.got();
    REQUIRE(got.size() == 5);
    CHECK(got[4].body == R"({"n":4})");
  }
  SECTION("a dead receiver: one last try without the back-off's wait, then dropped") {
    const std::string dead = "http://127.0.0.1:" + std::to_string(closed_port()) + "/hook";
    serve::NotifyOptions o;
    o.webhook = dead;
    o.attempts = 5;
    o.backoff_ms = 60000;
    Log log;
    o.log = log.sink();
    const auto t0 = std::chrono::steady_clock::now();
    {
      serve::Notifier n(o);
      n.send(R"({"event":"drift"})");
      // Until the first attempt has failed and the minute's wait begun.
      for (int i = 0; i < 500 && log.get().empty(); ++i) std::this_thread::sleep_for(10ms);
    }
    CHECK(std::chrono::steady_clock::now() - t0 < 10s);
    CHECK(log.get() ==
          std::vector<std::string>{
              "webhook " + dead + ": Connection; attempt 1 of 5, next in 60000 ms",
              "webhook " + dead + ": stopping, event dropped: " + R"({"event":"drift"})"});
  }
}

}  // namespace serve_test_notify

#pragma once
// lmcfg serve over a simulated RS485 line for the tests: two commissioned
// axes (sim:A.json,B.json state files the test may change behind the
// service's back), a Service with an injected clock, and an HttpServer on
// 127.0.0.1:0 served from a thread.
#include <catch2/catch.hpp>
#include <filesystem>
#include <mutex>
#include <nlohmann/json.hpp>
#include <optional>
#include <thread>

#include "files.hpp"
#include "ops/session.hpp"
#include "serve/http.hpp"
#include "serve/service.hpp"
#include "sim/state_file.hpp"

namespace lmcfg::test {

// The commissioned axis at MACID `id`, with UPID `upid` set to `value` (ROM and RAM).
inline void write_axis(const std::filesystem::path& path, int id, const std::string& upid = "",
                       int value = 0) {
  auto j = nlohmann::json::parse(
      slurp(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json"));
  j["macid"] = id;
  for (auto& p : j["parameters"])
    if (p["upid"] == upid) p["rom"] = p["ram"] = value;
  spit(path, j.dump(1));
}

struct ServeRig {
  ScratchDir dir{"serve"};
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  std::mutex mu;
  std::vector<nlohmann::json> events;
  std::unique_ptr<serve::Service> service;

  // `extra_toml` goes before the line (schedule, notify); `line_name` and
  // `z_keys` (more keys of press3/z, e.g. labels) let a test choose hostile text.
  explicit ServeRig(const std::string& extra_toml = "", const std::string& line_name = "\"line1\"",
                    const std::string& z_keys = "") {
    ops::register_link_scheme("sim", sim::state_file_link_factory());
    write_axis(dir.path / "a.json", 0x11);
    write_axis(dir.path / "b.json", 0x12);
    const std::string text = "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n" +
                             extra_toml + "[[line]]\nname = " + line_name +
                             "\nport = \"sim:" + (dir.path / "a.json").string() + "," +
                             (dir.path / "b.json").string() +
                             "\"\nignore = [\"0020h\"]\n"
                             "[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n" +
                             z_keys + "[[line.drive]]\nname = \"press3/x\"\nid = 0x12\n";
    auto inv = fleet::parse_inventory(text, "plant.toml");
    INFO((inv.ok() ? "" : inv.error().message));
    REQUIRE(inv.ok());
    serve::ServiceOptions o;
    o.inventory = *inv;
    o.archive = (dir.path / "archive").string();
    ops::LinkOptions link;
    link.port = inv->lines[0].port;
    o.links = {link};
    o.exit_code = [](const Error& e) { return e.code == Errc::not_found ? 2 : 4; };
    o.clock = [this] { return now; };
    o.notify = [this](const serve::Json& e) {
      std::lock_guard<std::mutex> lock(mu);
      events.push_back(nlohmann::json::parse(e.dump()));
    };
    auto s = serve::Service::create(std::move(o));
    REQUIRE(s.ok());
    service = std::move(s).value();
  }
  void at(serve::TimePoint t) {
    now = t;
    service->tick(t);
    service->wait_idle();
  }
  std::vector<nlohmann::json> take_events() {
    std::lock_guard<std::mutex> lock(mu);
    return std::exchange(events, {});
  }
};

struct ServeHttp {
  std::unique_ptr<serve::HttpServer> http;
  std::thread thread;
  int port = 0;
  ServeHttp(serve::Service& s, std::optional<std::vector<serve::TokenEntry>> tokens = std::nullopt,
            serve::ConsoleOptions console = {}) {
    serve::HttpOptions o;
    o.listen = {"127.0.0.1", 0};
    o.tokens = std::move(tokens);
    o.exit_code = [](const Error& e) { return e.code == Errc::not_found ? 2 : 70; };
    o.console = std::move(console);
    http = std::make_unique<serve::HttpServer>(s, o);
    auto p = http->bind();
    REQUIRE(p.ok());
    port = *p;
    thread = std::thread([this] { http->serve(); });
  }
  ~ServeHttp() {
    http->stop();
    thread.join();
  }
};

}  // namespace lmcfg::test

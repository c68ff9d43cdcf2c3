#pragma once
// lmcfg serve's Service over a simulated RS485 line of two drives (sim:A,B
// state files, changed behind its back by the tests), with an injected clock
// and the events it sends kept; Server: its HttpServer on 127.0.0.1, any port.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>
#include <vector>

#include "common/bytes.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "serve/http.hpp"
#include "serve/service.hpp"

namespace lmcfg::test {

namespace fs = std::filesystem;

// `git -C DIR ARGS` and its stdout.
inline std::string git(const fs::path& dir, const std::string& args) {
  const std::string cmd = "git -C '" + dir.string() + "' " + args + " 2>&1";
  std::string out;
  FILE* p = ::popen(cmd.c_str(), "r");
  REQUIRE(p);
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) out.append(buf, n);
  const int rc = ::pclose(p);
  INFO(cmd << "\n" << out);
  REQUIRE(rc == 0);
  return out;
}

// The CLI's exit code categories (README "Exit codes") for the errors these tests meet.
inline int exit_code_of(const Error& e) {
  if (e.code == Errc::not_found || e.code == Errc::invalid_argument) return 2;
  if (e.code == Errc::plan_refused) return 3;
  if (e.code == Errc::verify_mismatch) return 6;
  return 4;
}

inline const std::string kFixtures = std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/";

// The commissioned axis at MACID `id`, with UPID `upid` set to `value` (ROM and RAM).
// A new drive put at the position: every ROM and RAM value at its default
// (LinRS §10.2: nothing modified) except the LinRS settings a technician sets
// to put it on the line (baud rate and MACID source and value, 200Eh, 2012h,
// 206Ch, 2076h, as the commissioned axis has them); no curve, no command
// table entry.
inline void write_fresh_axis(const fs::path& path, int id) {
  auto j = nlohmann::json::parse(slurp(kFixtures + "commissioned-axis.json"));
  j["macid"] = hex(static_cast<std::uint32_t>(id), 2, "");
  for (auto& p : j["parameters"]) {
    const std::string upid = p["upid"];
    if (upid != "200E" && upid != "2012" && upid != "206C" && upid != "2076")
      p["rom"] = p["ram"] = p["default"];
    if (upid == "2076") p["rom"] = p["ram"] = id;  // on the line at its position's ID
  }
  j["curves"] = {{"flash", nlohmann::json::array()}};
  j["command_table"] = {{"flash", nlohmann::json::array()}};
  spit(path, j.dump(1));
}

// The commissioned axis takes its MACID "By Parameter" (206Ch = 3): LinRS §15
// "Take the value of MACID Parameter Value", so 2076h holds `id` too, or a
// reset would move the drive (to 11h, the fixture's, the line's first drive).
inline void write_axis(const fs::path& path, int id, const std::string& upid = "", int value = 0) {
  auto j = nlohmann::json::parse(test::slurp(kFixtures + "commissioned-axis.json"));
  j["macid"] = id;
  for (auto& p : j["parameters"]) {
    if (p["upid"] == "2076") p["rom"] = p["ram"] = id;
    if (p["upid"] == upid) p["rom"] = p["ram"] = value;
  }
  test::spit(path, j.dump(1));
}

// The simulated drive's state file with one option of the simulator set
// (docs/simulator.md: "silent_after_reset", ...).
inline void set_sim_option(const fs::path& state, const std::string& key,
                           const nlohmann::json& value) {
  auto j = nlohmann::json::parse(slurp(state));
  j["options"][key] = value;
  spit(state, j.dump(1));
}

// The simulated drive's state file without parameter `upid` ("3010"): a
// firmware that lacks it.
inline void drop_sim_parameter(const fs::path& state, const std::string& upid) {
  auto j = nlohmann::json::parse(slurp(state));
  auto& params = j["parameters"];
  for (auto it = params.begin(); it != params.end(); ++it)
    if ((*it)["upid"] == upid) {
      params.erase(it);
      break;
    }
  spit(state, j.dump(1));
}

// A serve::Service over an inventory's text (sim: ports), in a scratch
// directory of its own, on a clock the test sets, collecting the events it sends.
struct ServiceRig {
  ScratchDir dir;
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  std::mutex mu;
  std::vector<nlohmann::json> events;
  std::unique_ptr<serve::Service> service;

  explicit ServiceRig(const std::string& prefix) : dir(prefix) {}

  // The service over `inventory_text`, its archive in dir/archive, one link per
  // line on the line's port; `tweak` changes the options before it starts.
  void start(const std::string& inventory_text,
             const std::function<void(serve::ServiceOptions&)>& tweak = {}) {
    started_with = inventory_text;
    tweaked_with = tweak;
    auto inv = fleet::parse_inventory(inventory_text, "plant.toml");
    INFO((inv.ok() ? "" : inv.error().message));
    REQUIRE(inv.ok());
    serve::ServiceOptions o;
    o.inventory = *inv;
    o.archive = (dir.path / "archive").string();
    for (const auto& l : inv->lines) {
      link::LinkSpec link;
      link.port = *link::parse_port(l.port);
      o.links.push_back(link);
    }
    o.clock = [this] { return now; };
    // A live read (diff to=live, plan) on the simulator is waited for: the
    // tests of its bounded wait set their own (test_service_live.cpp).
    o.live_wait = std::chrono::minutes(1);
    o.notify = [this](const serve::Json& e) {
      std::lock_guard<std::mutex> lock(mu);
      events.push_back(nlohmann::json::parse(e.dump()));
    };
    if (tweak) tweak(o);
    auto s = serve::Service::create(std::move(o));
    REQUIRE(s.ok());
    service = std::move(s).value();
  }
  // The service stopped and started again on the same archive and state
  // directory (a restart of lmcfg serve).
  void restart() {
    service.reset();
    const std::string text = started_with;
    const auto tweak = tweaked_with;
    start(text, tweak);
  }
  std::string started_with;
  std::function<void(serve::ServiceOptions&)> tweaked_with;
  // The jobs due at `t`, run to the end.
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

// The service over a line of two simulated axes, press3/z (11h) and press3/x (12h).
struct Rig : ServiceRig {
  // extra_toml: top-level keys (before [schedule]); line_toml: keys of the
  // line; line_name: the line's name as TOML; z_toml: keys of press3/z (labels).
  explicit Rig(const std::string& extra_toml = "", const std::string& line_toml = "",
               const std::string& line_name = "\"line1\"", const std::string& z_toml = "")
      : ServiceRig("serve") {
    write_axis(dir.path / "a.json", 0x11);
    write_axis(dir.path / "b.json", 0x12);
    start(extra_toml + "[schedule]\nbackup_every = \"6h\"\nstatus_every = \"15m\"\n" +
              "[[line]]\nname = " + line_name + "\nport = 'sim:" + (dir.path / "a.json").string() +
              "," + (dir.path / "b.json").string() + "'\nignore = [\"0020h\"]\n" + line_toml +
              "[[line.drive]]\nname = \"press3/z\"\nid = 0x11\n" + z_toml +
              "[[line.drive]]\nname = \"press3/x\"\nid = 0x12\n",
          [](serve::ServiceOptions& o) { o.exit_code = exit_code_of; });
  }
};

struct Server {
  std::unique_ptr<serve::HttpServer> http;
  std::thread thread;
  int port = 0;
  Server(serve::Service& s, std::optional<std::vector<serve::TokenEntry>> tokens = std::nullopt,
         serve::ConsoleOptions console = {})
      : Server(s, options(std::move(tokens), std::move(console))) {}
  // The server with these options (tests of the options themselves).
  Server(serve::Service& s, serve::HttpOptions o) {
    http = std::make_unique<serve::HttpServer>(s, std::move(o));
    auto p = http->bind();
    REQUIRE(p.ok());
    port = *p;
    thread = std::thread([this] { http->serve(); });
  }
  ~Server() {
    http->stop();
    thread.join();
  }
  // 127.0.0.1, any port, the CLI's exit codes.
  static serve::HttpOptions options(std::optional<std::vector<serve::TokenEntry>> tokens = {},
                                    serve::ConsoleOptions console = {}) {
    serve::HttpOptions o;
    o.console = std::move(console);
    o.listen = {"127.0.0.1", 0};
    o.tokens = std::move(tokens);
    o.exit_code = exit_code_of;
    return o;
  }
};

}  // namespace lmcfg::test

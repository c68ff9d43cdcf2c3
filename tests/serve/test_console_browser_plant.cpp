// The plant as a night-shift technician meets it, in headless Chromium
// against lmcfg serve on simulated drives (docs/console.md "Approved
// configurations"): a used spare put at a position stays in drift through
// two scheduled backups and a restart of the service; the operator restores
// the approved configuration; a deliberate change is approved with a reason;
// a restore the drive stops answering in fails in plain words, its automatic
// retry is shown and cancelled; a restore without the values the drive
// cannot take is amber with its list; the banner shows when the service
// stops answering. Screenshots of each page at 1280 and 768 px are kept in
// build/tests/console-shots/ (plant-*.png).
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>
#include <thread>

#include "console_walk.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_browser_plant {

using namespace lmcfg;
using json = nlohmann::json;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// The steps of one walk, named so their results can be looked up.
struct Walk {
  json steps = json::array();
  std::map<std::string, std::size_t> named;
  json result;
  void add(json st, const std::string& name = "") {
    if (!name.empty()) named[name] = steps.size();
    steps.push_back(std::move(st));
  }
  void read(const std::string& name) { add({{"op", "read"}}, name); }
  void go(const std::string& url) { add({{"op", "goto"}, {"url", url}}); }
  void submit(const std::string& selector) { add({{"op", "submit"}, {"selector", selector}}); }
  void eval(const std::string& expression, const std::string& name = "") {
    add({{"op", "eval"}, {"expression", expression}}, name);
  }
  // The page at 1280 and 768 px, read and photographed at each.
  void both(const std::string& name) {
    add({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
    read(name);
    add(test::console_shot("plant-" + name + "-1280.png"));
    eval(kTargets, name + "-targets");
    add({{"op", "viewport"}, {"width", 768}, {"height", 1024}});
    read(name + "-768");
    add(test::console_shot("plant-" + name + "-768.png"));
    add({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
  }
  // `offline`: the walk sees the service stop, so the browser logs failed requests.
  bool run(const fs::path& work, bool offline = false) {
    result = test::console_walk(work, steps);
    if (result.is_null()) return false;
    REQUIRE(result["steps"].size() == steps.size());
    if (!offline) CHECK(result["console_errors"] == json::array());
    CHECK(result["requests"] == json::array());
    return true;
  }
  const json& at(const std::string& name) const { return result["steps"][named.at(name)]; }
  std::string text(const std::string& name) const {
    return at(name)["value"]["text"].get<std::string>();
  }
  bool has(const std::string& name, const std::string& needle) const {
    INFO("step " << name << ": " << needle);
    return text(name).find(needle) != std::string::npos;
  }
  // Nothing wider than the window at 768 px (names and IDs do not force it).
  void fits(const std::string& name) const {
    INFO("step " << name);
    CHECK(at(name + "-768")["value"]["width"].get<int>() <= 768);
    CHECK(at(name + "-targets")["value"] == json::array());
  }

  // The visible controls a finger or a mouse aims at that are lower than 40 px.
  static constexpr const char* kTargets =
      "Array.from(document.querySelectorAll('button, a.button, select, "
      "input:not([type=hidden]):not([type=checkbox]), summary, td a, .links a, .crumbs a, "
      "label.check')).filter((e) => e.offsetParent !== null).map((e) => [e.tagName + ' ' + "
      "(e.id || e.textContent.trim().slice(0, 30)), e.getBoundingClientRect().height]).filter("
      "(p) => p[1] < 40)";
};

std::string status_of(test::Rig& rig, const std::string& name) {
  return (*rig.service->drive(name))["status"].get<std::string>();
}

}  // namespace

TEST_CASE(
    "console in Chromium: a used spare stays drift, the approved configuration is "
    "restored, a change approved, a failed restore's retry cancelled, a partial restore "
    "amber",
    "[serve][console][browser]") {
  test::Rig rig;
  rig.at(rig.now);  // commissioning: the first backup approves itself
  REQUIRE(status_of(rig, "press3/x") == "ok");
  // A used spare from stores at press3/x: another machine's value.
  test::write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(rig.now + 6h);  // two scheduled backups archive it, and do not approve it
  rig.at(rig.now + 6h);
  REQUIRE(status_of(rig, "press3/x") == "drift");
  const fs::path work = rig.dir.path;
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  auto server = std::make_unique<test::Server>(*rig.service, std::nullopt, copt);
  std::string base = "http://127.0.0.1:" + std::to_string(server->port);
  const std::string x = "/position?name=press3%2Fx", z = "/position?name=press3%2Fz";

  Walk a;
  a.go(base + "/");
  a.both("overview");
  a.go(base + x);
  a.both("spare-drift");
  a.eval(
      "Array.from(document.querySelectorAll('time[datetime]')).every((t) => "
      "t.title.endsWith(' UTC)'))",
      "local-times");
  if (!a.run(work)) return;
  CHECK(a.has("overview", "drift"));
  a.fits("overview");
  a.fits("spare-drift");
  CHECK(a.has("spare-drift", "Differences at the last check (each as the approved configuration"));
  CHECK(a.has("spare-drift", "Approved configuration:"));
  CHECK(a.at("local-times")["value"] == true);

  // A restart changes no status.
  const json before = json::parse(rig.service->drives().dump());
  server.reset();
  rig.restart();
  const json after = json::parse(rig.service->drives().dump());
  for (std::size_t i = 0; i < before.size(); ++i) {
    CHECK(after[i]["status"] == before[i]["status"]);
    CHECK(after[i]["differences"] == before[i]["differences"]);
    CHECK(after[i]["last_backup"] == before[i]["last_backup"]);
    CHECK(after[i]["approved"] == before[i]["approved"]);
  }
  server = std::make_unique<test::Server>(*rig.service, std::nullopt, copt);
  base = "http://127.0.0.1:" + std::to_string(server->port);

  // The operator restores the approved configuration onto the spare.
  Walk b;
  b.go(base + x);
  b.read("after-restart");
  b.submit("#replace");
  b.submit("#plan");
  b.both("plan");
  b.add({{"op", "fill"}, {"selector", "#reason"}, {"value", "spare from stores"}});
  b.submit("#execute");
  b.add({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 60000}},
        "restore-done");
  b.both("restored");
  REQUIRE(b.run(work));
  CHECK(b.has("after-restart", "drift"));
  CHECK(b.has("plan", "Will write 1 value."));
  CHECK(b.has("plan", "Write to the drive"));
  b.fits("plan");
  CHECK(b.at("restore-done")["value"] == true);
  CHECK(b.has("restored", "Restored and verified"));
  CHECK(status_of(rig, "press3/x") == "ok");

  // A deliberate change, archived by the next backup, approved with a reason.
  test::write_axis(rig.dir.path / "b.json", 0x12, "0010", 8);
  rig.at(rig.now + 6h);
  REQUIRE(status_of(rig, "press3/x") == "drift");
  Walk c;
  c.go(base + x);
  c.add({{"op", "fill"},
         {"selector", "form.approve input[name=reason]"},
         {"value", "new tool: longer stroke"}});
  c.submit("form.approve button");
  c.add({{"op", "wait"}, {"selector", "#live .status.s-ok"}, {"timeout_ms", 30000}}, "ok");
  c.both("approved");
  REQUIRE(c.run(work));
  CHECK(c.at("ok")["value"] == true);
  CHECK(c.has("approved", "new tool: longer stroke"));
  CHECK(status_of(rig, "press3/x") == "ok");

  // A restore that the drive stops answering in: plain words, then the
  // automatic retry on the position, cancelled.
  test::write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);
  test::set_sim_option(rig.dir.path / "a.json", "silent_after_reset", true);
  Walk d;
  d.go(base + z);
  d.submit("#replace");
  d.submit("#plan");
  d.add({{"op", "fill"}, {"selector", "#reason"}, {"value", "tuning lost"}});
  d.submit("#execute");
  d.add({{"op", "wait"}, {"selector", ".job-state[data-state=failed]"}, {"timeout_ms", 120000}},
        "failed-wait");
  d.both("failed");
  d.go(base + z);
  d.both("retry");
  d.submit("#cancel-retry");
  d.both("cancelled");
  REQUIRE(d.run(work));
  CHECK(d.at("failed-wait")["value"] == true);
  CHECK(d.has("failed", "stopped answering during the restore"));
  CHECK(d.has("failed", "What to check:"));
  CHECK(d.has("failed", "The service tries this restore again by itself"));
  CHECK(d.has("retry", "An automatic retry is waiting: automatic retry of job"));
  CHECK(d.has("retry", "(asked by local)"));
  CHECK(d.has("cancelled", "automatic retry cancelled by local"));
  CHECK_FALSE(d.has("cancelled", "An automatic retry is waiting"));
  d.fits("failed");
  d.fits("retry");

  // A drive whose firmware lacks a value of the approved configuration.
  test::set_sim_option(rig.dir.path / "a.json", "silent_after_reset", false);
  test::drop_sim_parameter(rig.dir.path / "b.json", "3010");
  auto spare = json::parse(test::slurp(rig.dir.path / "b.json"));
  for (auto& p : spare["parameters"])
    if (p["upid"] == "0010") p["rom"] = p["ram"] = 3;
  test::spit(rig.dir.path / "b.json", spare.dump(1));
  Walk e;
  e.go(base + x);
  e.submit("#replace");
  e.submit("#plan");
  e.both("plan-incompatible");
  e.eval("document.querySelector('#execute').disabled", "disabled-before");
  e.eval(
      "document.querySelector('#skip-incompatible').click(), "
      "document.querySelector('#execute').disabled",
      "disabled-after");
  e.add({{"op", "fill"}, {"selector", "#reason"}, {"value", "spare with older firmware"}});
  e.submit("#execute");
  e.add({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 60000}},
        "partial-done");
  e.both("partial");
  e.go(base + x);
  e.both("partial-position");
  REQUIRE(e.run(work));
  CHECK(e.has("plan-incompatible", "Cannot be restored as it stands"));
  CHECK(e.at("disabled-before")["value"] == true);
  CHECK(e.at("disabled-after")["value"] == false);
  CHECK(e.at("partial-done")["value"] == true);
  CHECK(e.has("partial", "Restored, except 1 value(s) this drive cannot take."));
  CHECK(e.has("partial", "3010h"));
  CHECK(e.has("partial-position", "drift"));
  CHECK(status_of(rig, "press3/x") == "drift");
  e.fits("plan-incompatible");
  e.fits("partial");

  // The service stops answering: the banner says so.
  Walk f;
  f.go(base + "/");
  f.add(test::console_shot("plant-ready.png", false));
  f.add({{"op", "wait"}, {"selector", "#offline:not([hidden])"}, {"timeout_ms", 30000}}, "banner");
  f.add(test::console_shot("plant-offline-1280.png", false));
  f.read("offline");
  const auto ready = test::console_shots_dir() / "plant-ready.png";
  fs::remove(ready);
  std::thread stopper([&server, ready] {
    for (int i = 0; i < 600 && !fs::exists(ready); ++i) std::this_thread::sleep_for(100ms);
    server.reset();
  });
  const bool ran = f.run(work, true);
  stopper.join();
  REQUIRE(ran);
  CHECK(f.at("banner")["value"] == true);
  CHECK(f.has("offline", "The lmcfg service is not answering"));
}

}  // namespace serve_test_console_browser_plant

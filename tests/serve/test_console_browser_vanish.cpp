// A restore whose drive vanishes during "save the command table to flash", in
// headless Chromium against lmcfg serve (docs/serve.md "Failed and partial
// restores"): the operator starts it from the console; the job fails with the
// drive partially configured and its motion control stopped; the drive's line
// cannot be opened, and the position page says so through each failed
// automatic retry (when, which job, why, and when the next is due); the drive
// returns, the retry completes and the position is ok. Each page is read and
// photographed at 1280 and 390 px (build/tests/console-shots/vanish-*.png), and
// none is wider than 390 px there.
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "console_walk.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_browser_vanish {

using namespace lmcfg;
using json = nlohmann::json;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// What the service says the drive holds when the restore stopped after
// "stop motion control" (service_restore.cpp drive_state_after).
constexpr const char* kStopped =
    "partially configured, and its motion control is stopped: the axis does not move until a "
    "restore completes";

// press3/z with command table entry 2 changed behind the service's back (its
// first position 80 84 1E 00 instead of 40 42 0F 00); `gone`: its flash saves
// never answered and the drive deaf for days after one (the simulator's
// unanswered_saves), so the restore stops during "save the command table to flash".
void vanish_table(const fs::path& state, bool gone) {
  test::write_axis(state, 0x11);
  auto j = json::parse(test::slurp(state));
  for (auto& e : j["command_table"]["flash"]) {
    if (e["entry"] != 2) continue;
    std::string data = e["data"];
    data.replace(data.find("40 42 0F 00 20 A1"), 11, "80 84 1E 00");
    e["data"] = data;
  }
  if (gone) {
    j["options"]["unanswered_saves"] = true;
    j["timing_us"]["flash_save"] = 1'000'000'000'000;
  }
  test::spit(state, j.dump(1));
}

json vanish_plain(const serve::Json& j) { return json::parse(j.dump()); }

// The steps of one walk, named so their results can be looked up; each page
// read and photographed at 1280 and at 390 px.
struct VanishWalk {
  json steps = json::array();
  std::map<std::string, std::size_t> named;
  json result;
  void add(json st, const std::string& name = "") {
    if (!name.empty()) named[name] = steps.size();
    steps.push_back(std::move(st));
  }
  void go(const std::string& url) { add({{"op", "goto"}, {"url", url}}); }
  void submit(const std::string& selector) { add({{"op", "submit"}, {"selector", selector}}); }
  void both(const std::string& name) {
    add({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
    add({{"op", "read"}}, name);
    add(test::console_shot("vanish-" + name + "-1280.png"));
    add({{"op", "viewport"}, {"width", 390}, {"height", 844}});
    add({{"op", "read"}}, name + "-390");
    add(test::console_shot("vanish-" + name + "-390.png"));
    add({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
  }
  bool run(const fs::path& work) {
    result = test::console_walk(work, steps);
    if (result.is_null()) return false;
    REQUIRE(result["steps"].size() == steps.size());
    CHECK(result["console_errors"] == json::array());
    CHECK(result["requests"] == json::array());
    return true;
  }
  const json& at(const std::string& name) const { return result["steps"][named.at(name)]; }
  // The page's text at 1280 px; the same words at 390 px, and nothing wider than 390 px.
  std::string text(const std::string& name) const {
    const std::string wide = at(name)["value"]["text"].get<std::string>();
    const json& narrow = at(name + "-390")["value"];
    INFO("page " << name << " at 390 px: " << narrow["width"] << " px wide");
    CHECK(narrow["width"].get<int>() <= 390);
    CHECK(narrow["text"].get<std::string>() == wide);
    return wide;
  }
};

bool shows(const std::string& page, const std::string& needle) {
  INFO("looking for: " << needle << "\nin: " << page);
  return page.find(needle) != std::string::npos;
}

}  // namespace

TEST_CASE(
    "console in Chromium: a drive gone during a flash save stays partially configured "
    "through the failed automatic retries, each listed, until the retry restores it",
    "[serve][console][browser][retry]") {
  test::Rig rig;
  rig.at(rig.now);  // commissioning: the first backup approves itself
  const fs::path state = rig.dir.path / "a.json";
  vanish_table(state, true);
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  test::Server server(*rig.service, std::nullopt, copt);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.port);
  const std::string z = base + "/position?name=press3%2Fz";
  const fs::path work = rig.dir.path;

  // The operator restores the approved configuration; the drive goes silent
  // in the command table's flash save.
  VanishWalk a;
  a.go(z);
  a.submit("#replace");
  a.submit("#plan");
  a.add({{"op", "fill"}, {"selector", "#reason"}, {"value", "table entry 2 lost"}});
  a.submit("#execute");
  a.add({{"op", "wait"}, {"selector", ".job-state[data-state=failed]"}, {"timeout_ms", 120000}},
        "failed-wait");
  a.both("failed");
  a.go(z);
  a.both("stopped");
  if (!a.run(work)) return;
  CHECK(a.at("failed-wait")["value"] == true);
  const std::string failed = a.text("failed");
  CHECK(shows(failed, "stopped answering during the restore."));
  CHECK(shows(failed, std::string("The drive is ") + kStopped + "."));
  CHECK(shows(failed, " step(s) before it stopped"));
  CHECK(shows(failed, "It stopped during: Saving the command table to the drive's flash"));
  CHECK(shows(failed, "The service tries this restore again by itself"));
  CHECK_FALSE(shows(failed, "untouched"));
  const std::string stopped = a.text("stopped");
  CHECK(shows(stopped, std::string("The drive is ") + kStopped + "."));
  CHECK(shows(stopped, "An automatic retry is waiting: automatic retry of job"));
  CHECK(shows(stopped, "(asked by local)"));
  CHECK_FALSE(shows(stopped, "automatic attempt(s) failed so far"));
  CHECK_FALSE(shows(stopped, "untouched"));
  auto d = vanish_plain(*rig.service->drive("press3/z"));
  REQUIRE(d["retry"].is_object());
  const std::string first = d["retry"]["of_job"];
  CHECK(d["drive_state"] == kStopped);

  // The drive is gone (its line cannot be opened): each automatic retry
  // fails on the connection, and the position lists it and the next.
  fs::remove(state);
  for (int attempt = 1; attempt <= 2; ++attempt) {
    rig.at(rig.now + 15min);
    d = vanish_plain(*rig.service->drive("press3/z"));
    INFO(d.dump());
    REQUIRE(d["retry"].is_object());
    REQUIRE(d["retry"]["failures"].size() == static_cast<std::size_t>(attempt));
    const std::string name = "retry-failed-" + std::to_string(attempt);
    VanishWalk w;
    w.go(z);
    w.both(name);
    REQUIRE(w.run(work));
    const std::string page = w.text(name);
    CHECK(shows(page, "failed"));
    CHECK(shows(page, std::string("The drive is ") + kStopped + "."));
    CHECK(shows(page, "An automatic retry is waiting: automatic retry of job " + first));
    CHECK(shows(page, std::to_string(attempt) +
                          " automatic attempt(s) failed so far; the next is due at " +
                          serve::iso_time(rig.now + 15min) + ":"));
    // Each failed attempt: its time, its job and why, as the service records them.
    for (const auto& f : d["retry"]["failures"]) {
      CHECK(f["job"] != first);
      CHECK(shows(page, f["time"].get<std::string>() + ", job " + f["job"].get<std::string>() +
                            ": " + f["reason"].get<std::string>()));
    }
    CHECK(d["retry"]["failures"].back()["time"] == serve::iso_time(rig.now));
    CHECK_FALSE(shows(page, "untouched"));
  }

  // The drive is back, its table as before the restore: the retry completes.
  vanish_table(state, false);
  rig.at(rig.now + 15min);
  d = vanish_plain(*rig.service->drive("press3/z"));
  INFO(d.dump());
  REQUIRE(d["status"] == "ok");
  std::string retry_job;
  for (unsigned long n = std::stoul(first) + 1; n < std::stoul(first) + 12; ++n)
    if (auto j = rig.service->job(std::to_string(n));
        j.ok() && (*j)["kind"] == "restore" && (*j)["state"] == "done")
      retry_job = std::to_string(n);
  REQUIRE_FALSE(retry_job.empty());
  VanishWalk r;
  r.go(z);
  r.both("restored");
  r.go(base + "/job?id=" + retry_job + "&name=press3%2Fz");
  r.both("retry-done");
  REQUIRE(r.run(work));
  const std::string restored = r.text("restored");
  CHECK(shows(restored, "ok " + d["message"].get<std::string>()));
  CHECK_FALSE(shows(restored, "automatic retry is waiting"));
  CHECK_FALSE(shows(restored, "partially configured"));
  CHECK_FALSE(shows(restored, "automatic attempt(s) failed"));
  const std::string done = r.text("retry-done");
  CHECK(shows(done, "Restored and verified"));
  CHECK(shows(done, "automatic retry of job " + first));
}

}  // namespace serve_test_console_browser_vanish

// The web console in headless Chromium at 390 px (a phone held upright): every
// page a technician opens while restoring a used spare (sign-in, overview,
// positions, replace, plan, progress and outcome, the plan reopened after it
// ran, an unknown job) is no wider than the screen (document.scrollWidth),
// and the plan and the outcome say which values stay as the drive holds them
// (docs/fleet.md "What matches means"). Screenshots in build/tests/console-shots/.
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "console_walk.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_browser_narrow {

using namespace lmcfg;
using json = nlohmann::json;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

// The spare's own LinRS settings (its switches choose baud rate and MACID),
// and Appl 3020h at -1000, which the plan writes back to its default.
void used_spare(const fs::path& state) {
  test::write_axis(state, 0x12, "0010", 7);
  auto j = json::parse(test::slurp(state));
  for (auto& p : j["parameters"]) {
    if (p["upid"] == "200E") p["rom"] = p["ram"] = 1;
    if (p["upid"] == "2012") p["rom"] = p["ram"] = 8;
    if (p["upid"] == "206C") p["rom"] = p["ram"] = 1;
    if (p["upid"] == "3020") p["rom"] = p["ram"] = 4294966296u;
  }
  test::spit(state, j.dump(1));
}

}  // namespace

TEST_CASE(
    "console in Chromium at 390 px: no page is wider than the screen, and the plan and the "
    "outcome list the values the drive keeps",
    "[serve][console][browser][matching]") {
  test::Rig rig;
  rig.at(rig.now);  // commissioned
  used_spare(rig.dir.path / "b.json");
  rig.at(rig.now + 6h);  // archived, in drift
  REQUIRE((*rig.service->drive("press3/x"))["status"] == "drift");

  const std::string tokens_file = (rig.dir.path / "tokens").string();
  const std::string op = *serve::add_token(tokens_file, "night-shift", serve::Role::operator_);
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  test::Server server(*rig.service, *serve::load_tokens(tokens_file), copt);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.port);

  json steps = json::array();
  std::map<std::string, std::size_t> named;
  std::vector<std::string> pages;  // the steps whose width is checked
  auto step = [&](json st, const std::string& name = "") {
    if (!name.empty()) named[name] = steps.size();
    steps.push_back(std::move(st));
  };
  auto read = [&](const std::string& name) {
    step({{"op", "read"}}, name);
    pages.push_back(name);
    step(test::console_shot("narrow-" + name + "-390.png"));
  };
  step({{"op", "viewport"}, {"width", 390}, {"height", 844}});
  step({{"op", "goto"}, {"url", base + "/"}});
  read("signin");
  step({{"op", "fill"}, {"selector", "#token"}, {"value", op}});
  step({{"op", "submit"}, {"selector", "form.card button[type=submit]"}});
  read("overview");
  step({{"op", "goto"}, {"url", base + "/position?name=press3%2Fx"}});
  read("position-drift");
  step({{"op", "goto"}, {"url", base + "/position?name=press3%2Fz"}});
  read("position-ok");
  step({{"op", "goto"}, {"url", base + "/replace?name=press3%2Fx"}});
  read("replace");
  step({{"op", "submit"}, {"selector", "#plan"}});
  read("plan");
  step({{"op", "fill"}, {"selector", "#reason"}, {"value", "spare back to the approved tuning"}});
  step({{"op", "submit"}, {"selector", "#execute"}});
  step({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 30000}},
       "restore-done");
  read("outcome");
  step({{"op", "goto"}, {"url", base + "/position?name=press3%2Fx"}});
  read("position-restored");
  step({{"op", "goto"}, {"url", base + "/job?id=999999"}});
  read("no-such-job");

  const json w = test::console_walk(rig.dir.path, steps);
  if (w.is_null()) return;
  const auto& s = w["steps"];
  REQUIRE(s.size() == steps.size());
  // The only console error: the unknown job's page answers 404, as it should.
  for (const auto& e : w["console_errors"])
    CHECK(e.get<std::string>().find("404") != std::string::npos);
  auto at = [&](const std::string& name) -> const json& { return s[named.at(name)]; };
  auto text = [&](const std::string& name) { return at(name)["value"]["text"].get<std::string>(); };
  for (const auto& p : pages) {
    INFO("page " << p << " at " << at(p)["url"] << ": " << at(p)["value"]["width"] << " px");
    CHECK(at(p)["value"]["width"].get<int>() <= 390);
  }
  CHECK(at("restore-done")["value"] == true);
  // Before the write: the three communication values stay, with why and what to do.
  CHECK(text("plan").find("What stays different") != std::string::npos);
  CHECK(text("plan").find("the drive keeps 8") != std::string::npos);
  CHECK(text("plan").find("Nothing needs doing while the drive answers on its line.") !=
        std::string::npos);
  // After it: verified, and the same values said again.
  CHECK(text("outcome").find("Restored and verified") != std::string::npos);
  CHECK(text("outcome").find("What stays different") != std::string::npos);
  CHECK(text("position-restored").find("What stays different") != std::string::npos);
  CHECK((*rig.service->drive("press3/x"))["status"] == "ok");
}

}  // namespace serve_test_console_browser_narrow

// The web console in headless Chromium (tests/browser/walk-console.js over
// the DevTools protocol) against lmcfg serve on simulated drives: a
// technician signs in as operator, reads the overview, backs up a drifted
// position from its button, then replaces a drive: the factory-fresh drive
// at press3/x is checked and planned, the plan confirmed with a reason, the
// progress watched, the verify result read, and the commit with the reason
// found in the position's history. Screenshots of each page at 1280 px and
// 768 px are kept in build/tests/console-shots/.
#include <catch2/catch.hpp>
#include <map>
#include <nlohmann/json.hpp>

#include "console_walk.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_browser {

using namespace lmcfg;
using json = nlohmann::json;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

fs::path shots_dir() { return test::console_shots_dir(); }
json walk(const fs::path& work, const json& steps) { return test::console_walk(work, steps); }
json shot(const std::string& name, bool full_page = true) {
  return test::console_shot(name, full_page);
}

}  // namespace

TEST_CASE(
    "console in Chromium: sign in as operator, overview at 1280 and 768 px, back up a "
    "drifted position, replace a drive through plan, confirm, progress and verify",
    "[serve][console][browser]") {
  // press3/z (the line's first drive, with hostile labels) is swapped for a
  // factory-fresh drive; press3/x is tuned by hand.
  test::Rig rig("", "", "\"line1\"",
                "labels = { machine = \"press3\", note = \"<img src=x onerror=alert(1)>\" }\n");
  rig.at(rig.now);  // the first backup and drift check
  test::write_fresh_axis(rig.dir.path / "a.json", 0x11);
  test::write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(rig.now + 15min);
  REQUIRE((*rig.service->drive("press3/z"))["status"] == "replaced");
  REQUIRE((*rig.service->drive("press3/x"))["status"] == "drift");

  const std::string tokens_file = (rig.dir.path / "tokens").string();
  const std::string op = *serve::add_token(tokens_file, "night-shift", serve::Role::operator_);
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  test::Server server(*rig.service, *serve::load_tokens(tokens_file), copt);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.port);
  const std::string replaced = base + "/position?name=press3%2Fz";
  const std::string drifted = base + "/position?name=press3%2Fx";
  const std::string reason = "encoder fault, drive swapped <b>&amp;</b>";

  // Each step may have a name: its result is looked up by it.
  json steps = json::array();
  std::map<std::string, std::size_t> named;
  auto step = [&](json st, const std::string& name = "") {
    if (!name.empty()) named[name] = steps.size();
    steps.push_back(std::move(st));
  };
  auto read = [&](const std::string& name) { step({{"op", "read"}}, name); };
  step({{"op", "goto"}, {"url", drifted}});  // no session: the sign-in page
  read("signin");
  step(shot("01-signin-1280.png", false));
  step({{"op", "fill"}, {"selector", "#token"}, {"value", op}});
  step({{"op", "submit"}, {"selector", "form.card button[type=submit]"}});  // back to press3/x
  read("signed-in");
  step({{"op", "goto"}, {"url", base + "/"}});
  read("overview");
  step({{"op", "tab"}, {"count", 1}}, "tab");  // the skip link, focus visible
  step(shot("02-overview-1280.png"));
  step({{"op", "viewport"}, {"width", 768}, {"height", 1024}});
  read("overview-768");
  step(shot("03-overview-768.png"));
  step({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
  step({{"op", "goto"}, {"url", drifted}});
  step(shot("04-position-drift-1280.png"));
  step({{"op", "submit"}, {"selector", "#backup-now"}});  // the backup job's page
  step({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 20000}},
       "backup-done");
  read("backup-job");
  step({{"op", "goto"}, {"url", replaced}});
  read("replaced");  // the labels, as text
  step({{"op", "submit"}, {"selector", "#replace"}});
  read("replace");  // which revision
  step(shot("05-replace-1280.png"));
  step({{"op", "submit"}, {"selector", "#plan"}});  // the drive read, the plan
  read("plan");
  step(shot("06-plan-1280.png"));
  step({{"op", "viewport"}, {"width", 768}, {"height", 1024}});
  read("plan-768");
  step(shot("07-plan-768.png"));
  step({{"op", "viewport"}, {"width", 1280}, {"height", 900}});
  step({{"op", "fill"}, {"selector", "#reason"}, {"value", reason}});
  step({{"op", "fill"}, {"selector", "#ticket"}, {"value", "MAINT-4711"}});
  step({{"op", "submit"}, {"selector", "#execute"}});  // the restore job's progress
  step({{"op", "eval"}, {"expression", "document.querySelector('progress') !== null"}}, "progress");
  step({{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 30000}},
       "restore-done");
  read("restore-job");  // the verify result and the commit
  step(shot("08-restore-done-1280.png"));
  step({{"op", "goto"}, {"url", replaced}});
  read("history");  // the restore with its reason
  step(shot("09-position-history-1280.png"));
  step({{"op", "submit"}, {"selector", "#live-diff"}});  // the diff with the drive, as a report
  read("live-diff");
  step(shot("10-live-diff-1280.png", false));

  const json w = walk(rig.dir.path, steps);
  if (w.is_null()) return;
  const auto& s = w["steps"];
  REQUIRE(s.size() == steps.size());
  CHECK(w["console_errors"] == json::array());
  CHECK(w["requests"] == json::array());  // nothing from outside the console
  CHECK(w["dialogs"] == json::array());   // no hostile label ran
  auto at = [&](const std::string& name) -> const json& { return s[named.at(name)]; };
  auto has = [&](const std::string& name, const std::string& needle) {
    INFO("step " << name << ": " << needle);
    return at(name)["value"]["text"].get<std::string>().find(needle) != std::string::npos;
  };

  CHECK(at("signin")["value"]["h1"] == "Sign in");
  CHECK(at("signin")["url"].get<std::string>().rfind(base + "/signin?next=", 0) == 0);
  CHECK(at("signed-in")["url"] == drifted);
  CHECK(at("signed-in")["value"]["h1"].get<std::string>().rfind("press3/x", 0) == 0);
  CHECK(has("signed-in", "night-shift (operator)"));

  CHECK(has("overview", "2 positions"));
  CHECK(at("overview")["value"]["scripts"] == 0);  // no inline script: the CSP would block it
  CHECK(at("tab")["value"]["text"] == "Skip to content");
  CHECK(at("tab")["value"]["outline"] == "solid");
  CHECK(at("tab")["value"]["outline_width"].get<double>() >= 2);
  CHECK(at("overview-768")["value"]["width"].get<int>() <= 768);  // no sideways scrolling

  CHECK(at("backup-done")["value"] == true);  // the script's refresh showed the job finished
  CHECK(at("backup-job")["url"].get<std::string>().rfind(base + "/job?id=", 0) == 0);
  CHECK(has("backup-job", "Committed:"));

  CHECK(has("replaced", "<img src=x onerror=alert(1)>"));
  CHECK(at("replaced")["value"]["handlers"] == 0);
  CHECK(at("replace")["url"] == base + "/replace?name=press3%2Fz");
  CHECK(has("replace", "Check the drive and plan"));
  CHECK(at("plan")["url"].get<std::string>().rfind(base + "/plan?id=", 0) == 0);
  CHECK(has("plan", "A drive answers on line line1 with ID 11h."));
  CHECK(has("plan", "It is factory-fresh"));
  CHECK(has("plan", "What will be written"));
  CHECK(at("plan-768")["value"]["width"].get<int>() <= 768);

  CHECK(at("progress")["value"] == true);  // the progress bar
  CHECK(at("restore-done")["value"] == true);
  CHECK(at("restore-job")["url"].get<std::string>().rfind(base + "/job?id=", 0) == 0);
  CHECK(has("restore-job", "Restored and verified"));
  CHECK(has("restore-job", "asked by night-shift"));
  CHECK(has("restore-job", "Recorded in the archive as commit"));

  CHECK((*rig.service->drive("press3/z"))["status"] == "ok");
  const auto h = *rig.service->history("press3/z");
  REQUIRE(h.size() >= 2);
  const std::string record = h[0]["commit"];
  CHECK(h[0]["message"].get<std::string>().find("Reason: " + reason) != std::string::npos);
  CHECK(has("restore-job", record));
  CHECK(has("history", record.substr(0, 10)));
  CHECK(has("history", reason));  // the reason, as text
  CHECK(has("history", "MAINT-4711"));
  CHECK(has("history", "night-shift"));

  CHECK(at("live-diff")["url"] == base + "/diff?name=press3%2Fz&from=HEAD&to=live");
  CHECK(has("live-diff", "drive press3/z (live)"));
  CHECK(has("live-diff", "Identical"));  // restored: the drive holds the archived file
  CHECK(at("live-diff")["value"]["scripts"] == 0);
  for (const char* f :
       {"01-signin-1280.png", "02-overview-1280.png", "03-overview-768.png",
        "04-position-drift-1280.png", "05-replace-1280.png", "06-plan-1280.png", "07-plan-768.png",
        "08-restore-done-1280.png", "09-position-history-1280.png", "10-live-diff-1280.png"})
    CHECK(fs::file_size(shots_dir() / f) > 5000);
}

}  // namespace serve_test_console_browser

// The web console in headless Chromium (tests/browser/walk-console.js over
// the DevTools protocol) against lmcfg serve on simulated drives: a
// technician signs in as operator, reads the overview, backs up a drifted
// position from its button, then replaces a drive: the factory-fresh drive
// at press3/x is checked and planned, the plan confirmed with a reason, the
// progress watched, the verify result read, and the commit with the reason
// found in the position's history. Screenshots of each page at 1280 px and
// 768 px are kept in build/tests/console-shots/.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "browser.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

using namespace lmcfg;
using json = nlohmann::json;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

fs::path shots_dir() {
  const fs::path d = fs::path(LMCFG_BINARY_DIR) / "tests" / "console-shots";
  fs::create_directories(d);
  return d;
}

// Runs the steps in Chromium; the walk's JSON, or null when skipped.
json walk(const fs::path& work, const json& steps) {
  const std::string chromium = test::find_chromium();
  if (chromium.empty()) {
    if (test::browser_required()) FAIL("chromium not found, and LMCFG_REQUIRE_BROWSER=1");
    WARN("SKIP: console browser walk: chromium not found (apt-get install chromium)");
    return nullptr;
  }
  test::spit(work / "steps.json", steps.dump(1));
  const std::string cmd =
      "node '" + std::string(LMCFG_SOURCE_DIR) + "/tests/browser/walk-console.js' --chromium '" +
      chromium + "' --steps '" + (work / "steps.json").string() + "' >'" +
      (work / "walk.json").string() + "' 2>'" + (work / "walk.err").string() + "'";
  const int rc = std::system(cmd.c_str());
  INFO(test::slurp(work / "walk.err"));
  REQUIRE(rc == 0);
  return json::parse(test::slurp(work / "walk.json"));
}

json shot(const std::string& name, bool full_page = true) {
  return {{"op", "shot"}, {"file", (shots_dir() / name).string()}, {"full_page", full_page}};
}

}  // namespace

TEST_CASE(
    "console in Chromium: sign in as operator, overview at 1280 and 768 px, back up a "
    "drifted position, replace a drive through plan, confirm, progress and verify",
    "[serve][console][browser]") {
  test::Rig rig("", "", "\"line1\"",
                "labels = { machine = \"press3\", note = \"<img src=x onerror=alert(1)>\" }\n");
  rig.at(rig.now);                                             // the first backup and drift check
  test::write_axis(rig.dir.path / "a.json", 0x11, "0010", 7);  // press3/z tuned by hand
  test::write_fresh_axis(rig.dir.path / "b.json", 0x12);       // press3/x swapped for a new drive
  rig.at(rig.now + 15min);
  REQUIRE((*rig.service->drive("press3/z"))["status"] == "drift");
  REQUIRE((*rig.service->drive("press3/x"))["status"] == "replaced");

  const std::string tokens_file = (rig.dir.path / "tokens").string();
  const std::string op = *serve::add_token(tokens_file, "night-shift", serve::Role::operator_);
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  test::Server server(*rig.service, *serve::load_tokens(tokens_file), copt);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.port);
  const std::string z = base + "/position?name=press3%2Fz";
  const std::string x = base + "/position?name=press3%2Fx";
  const std::string reason = "encoder fault, drive swapped <b>&amp;</b>";

  json steps = json::array({
      {{"op", "goto"}, {"url", z}},  // 0: no session: the sign-in page
      {{"op", "read"}},
      shot("01-signin-1280.png", false),
      {{"op", "fill"}, {"selector", "#token"}, {"value", op}},
      {{"op", "submit"}, {"selector", "form.card button[type=submit]"}},  // 4: back to press3/z
      {{"op", "read"}},
      {{"op", "goto"}, {"url", base + "/"}},  // 6
      {{"op", "read"}},
      {{"op", "tab"}, {"count", 1}},  // 8: the skip link, focus visible
      shot("02-overview-1280.png"),
      {{"op", "viewport"}, {"width", 768}, {"height", 1024}},  // 10
      {{"op", "read"}},
      shot("03-overview-768.png"),
      {{"op", "viewport"}, {"width", 1280}, {"height", 900}},
      {{"op", "goto"}, {"url", z}},  // 14: labels as text
      {{"op", "read"}},
      shot("04-position-drift-1280.png"),
      {{"op", "submit"}, {"selector", "#backup-now"}},  // 17: the job page
      {{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 20000}},
      {{"op", "read"}},              // 19
      {{"op", "goto"}, {"url", x}},  // 20: the replaced drive
      {{"op", "submit"}, {"selector", "#replace"}},
      {{"op", "read"}},  // 22: which revision
      shot("05-replace-1280.png"),
      {{"op", "submit"}, {"selector", "#plan"}},  // 24: the drive read, the plan
      {{"op", "read"}},
      shot("06-plan-1280.png"),
      {{"op", "viewport"}, {"width", 768}, {"height", 1024}},
      {{"op", "read"}},  // 28
      shot("07-plan-768.png"),
      {{"op", "viewport"}, {"width", 1280}, {"height", 900}},
      {{"op", "fill"}, {"selector", "#reason"}, {"value", reason}},
      {{"op", "fill"}, {"selector", "#ticket"}, {"value", "MAINT-4711"}},
      {{"op", "submit"}, {"selector", "#execute"}},  // 33: the restore job's progress
      {{"op", "eval"}, {"expression", "document.querySelector('progress') !== null"}},
      {{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 30000}},
      {{"op", "read"}},  // 36: the verify result and the commit
      shot("08-restore-done-1280.png"),
      {{"op", "goto"}, {"url", x}},
      {{"op", "read"}},  // 39: the history has the restore with its reason
      shot("09-position-history-1280.png"),
      {{"op", "submit"}, {"selector", "#live-diff"}},  // 41: the diff with the drive, as a report
      {{"op", "read"}},
      shot("10-live-diff-1280.png", false),
  });
  const json w = walk(rig.dir.path, steps);
  if (w.is_null()) return;
  const auto& s = w["steps"];
  REQUIRE(s.size() == steps.size());
  CHECK(w["console_errors"] == json::array());
  CHECK(w["requests"] == json::array());  // nothing from outside the console
  CHECK(w["dialogs"] == json::array());   // no hostile label ran
  auto text = [&](std::size_t i) { return s[i]["value"]["text"].get<std::string>(); };
  auto has = [&](std::size_t i, const std::string& needle) {
    INFO("step " << i << ": " << needle);
    return text(i).find(needle) != std::string::npos;
  };

  CHECK(s[1]["value"]["h1"] == "Sign in");
  CHECK(s[1]["url"].get<std::string>().rfind(base + "/signin?next=", 0) == 0);
  CHECK(s[5]["url"] == z);
  CHECK(s[5]["value"]["h1"].get<std::string>().rfind("press3/z", 0) == 0);
  CHECK(has(5, "night-shift (operator)"));

  CHECK(has(7, "2 positions"));
  CHECK(s[7]["value"]["scripts"] == 0);  // no inline script: the CSP would block it
  CHECK(s[8]["value"]["text"] == "Skip to content");
  CHECK(s[8]["value"]["outline"] == "solid");
  CHECK(s[8]["value"]["outline_width"].get<double>() >= 2);
  CHECK(s[11]["value"]["width"].get<int>() <= 768);  // no sideways scrolling on a tablet

  CHECK(has(15, "<img src=x onerror=alert(1)>"));
  CHECK(s[15]["value"]["handlers"] == 0);

  CHECK(s[18]["value"] == true);  // the script's refresh showed the job finished
  CHECK(s[19]["url"].get<std::string>().rfind(base + "/job?id=", 0) == 0);
  CHECK(has(19, "Committed:"));

  CHECK(s[22]["url"] == base + "/replace?name=press3%2Fx");
  CHECK(has(22, "Check the drive and plan"));
  CHECK(s[25]["url"].get<std::string>().rfind(base + "/plan?id=", 0) == 0);
  CHECK(has(25, "A drive answers on line line1 as ID 12h."));
  CHECK(has(25, "It is factory-fresh"));
  CHECK(has(25, "What will be written"));
  CHECK(s[28]["value"]["width"].get<int>() <= 768);

  CHECK(s[34]["value"] == true);  // the progress bar
  CHECK(s[35]["value"] == true);
  CHECK(s[36]["url"].get<std::string>().rfind(base + "/job?id=", 0) == 0);
  CHECK(has(36, "Outcome: "));
  CHECK(has(36, "and verified"));
  CHECK(has(36, "asked by night-shift"));
  CHECK(has(36, "Recorded in the archive as commit"));

  CHECK((*rig.service->drive("press3/x"))["status"] == "ok");
  const auto h = *rig.service->history("press3/x");
  REQUIRE(h.size() >= 2);
  const std::string record = h[0]["commit"];
  CHECK(h[0]["message"].get<std::string>().find("Reason: " + reason) != std::string::npos);
  CHECK(has(36, record));
  CHECK(has(39, record.substr(0, 10)));
  CHECK(has(39, reason));  // the reason, as text
  CHECK(has(39, "MAINT-4711"));
  CHECK(has(39, "night-shift"));
  CHECK(s[42]["url"] == base + "/diff?name=press3%2Fx&from=HEAD&to=live");
  CHECK(has(42, "drive press3/x (live)"));
  CHECK(s[42]["value"]["scripts"] == 0);
  for (const char* f :
       {"01-signin-1280.png", "02-overview-1280.png", "03-overview-768.png",
        "04-position-drift-1280.png", "05-replace-1280.png", "06-plan-1280.png", "07-plan-768.png",
        "08-restore-done-1280.png", "09-position-history-1280.png", "10-live-diff-1280.png"})
    CHECK(fs::file_size(shots_dir() / f) > 5000);
}

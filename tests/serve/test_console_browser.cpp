// The web console in headless Chromium (tests/browser/walk-console.js over
// the DevTools protocol) against lmcfg serve on simulated drives: a
// technician signs in as operator, reads the overview, opens a drifted
// position, backs it up from the button and watches the job finish, then
// finds the commit in the history. Screenshots of each page at 1280 px and
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
    "drifted position, its commit in the history",
    "[serve][console][browser]") {
  test::Rig rig("", "", "\"line1\"",
                "labels = { machine = \"press3\", note = \"<img src=x onerror=alert(1)>\" }\n");
  rig.at(rig.now);                                             // the first backup and drift check
  test::write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);  // press3/x tuned by hand
  rig.at(rig.now + 15min);
  REQUIRE((*rig.service->drive("press3/x"))["status"] == "drift");

  const std::string tokens_file = (rig.dir.path / "tokens").string();
  const std::string op = *serve::add_token(tokens_file, "night-shift", serve::Role::operator_);
  serve::ConsoleOptions copt;
  copt.clock = [&rig] { return rig.now; };
  test::Server server(*rig.service, *serve::load_tokens(tokens_file), copt);
  const std::string base = "http://127.0.0.1:" + std::to_string(server.port);
  const std::string x = base + "/position?name=press3%2Fx";

  json steps = json::array({
      {{"op", "goto"}, {"url", x}},  // 0: no session: the sign-in page
      {{"op", "read"}},
      shot("01-signin-1280.png", false),
      {{"op", "fill"}, {"selector", "#token"}, {"value", op}},
      {{"op", "submit"}, {"selector", "form.card button[type=submit]"}},  // 4: back to press3/x
      {{"op", "read"}},
      {{"op", "goto"}, {"url", base + "/"}},  // 6
      {{"op", "read"}},
      {{"op", "tab"}, {"count", 1}},  // 8: the skip link, focus visible
      shot("02-overview-1280.png"),
      {{"op", "viewport"}, {"width", 768}, {"height", 1024}},  // 10
      {{"op", "read"}},
      shot("03-overview-768.png"),
      {{"op", "viewport"}, {"width", 1280}, {"height", 900}},
      {{"op", "goto"}, {"url", base + "/position?name=press3%2Fz"}},  // 14: labels as text
      {{"op", "read"}},
      {{"op", "goto"}, {"url", x}},  // 16
      shot("04-position-drift-1280.png"),
      {{"op", "submit"}, {"selector", "#backup-now"}},  // 18: the job page
      {{"op", "wait"}, {"selector", ".job-state[data-state=done]"}, {"timeout_ms", 20000}},
      shot("05-backup-job-1280.png"),
      {{"op", "read"}},  // 21
      {{"op", "goto"}, {"url", x}},
      {{"op", "read"}},  // 23: the history has the backup's commit
      shot("06-position-history-1280.png"),
  });
  const json w = walk(rig.dir.path, steps);
  if (w.is_null()) return;
  const auto& s = w["steps"];
  REQUIRE(s.size() == steps.size());
  CHECK(w["console_errors"] == json::array());
  CHECK(w["requests"] == json::array());  // nothing from outside the console
  CHECK(w["dialogs"] == json::array());   // no hostile label ran

  CHECK(s[1]["value"]["h1"] == "Sign in");
  CHECK(s[1]["url"].get<std::string>().rfind(base + "/signin?next=", 0) == 0);
  CHECK(s[5]["url"] == x);
  CHECK(s[5]["value"]["h1"].get<std::string>().rfind("press3/x", 0) == 0);
  CHECK(s[5]["value"]["text"].get<std::string>().find("night-shift (operator)") !=
        std::string::npos);

  const std::string overview = s[7]["value"]["text"];
  CHECK(overview.find("2 positions") != std::string::npos);
  CHECK(s[7]["value"]["scripts"] == 0);  // no inline script: the CSP would block it
  CHECK(s[8]["value"]["text"] == "Skip to content");
  CHECK(s[8]["value"]["outline"] == "solid");
  CHECK(s[8]["value"]["outline_width"].get<double>() >= 2);
  CHECK(s[11]["value"]["width"].get<int>() <= 768);  // no sideways scrolling on a tablet

  CHECK(s[15]["value"]["text"].get<std::string>().find("<img src=x onerror=alert(1)>") !=
        std::string::npos);
  CHECK(s[15]["value"]["handlers"] == 0);

  CHECK(s[19]["value"] == true);  // the script's refresh showed the job finished
  CHECK(s[21]["url"].get<std::string>().rfind(base + "/job?id=", 0) == 0);
  const std::string job = s[21]["value"]["text"];
  CHECK(job.find("Committed:") != std::string::npos);

  const std::string history = s[23]["value"]["text"];
  CHECK(history.find("press3/x") != std::string::npos);
  const auto h = *rig.service->history("press3/x");
  REQUIRE(h.size() == 2);
  CHECK(history.find(h[0]["commit"].get<std::string>().substr(0, 10)) != std::string::npos);
  for (const char* f :
       {"01-signin-1280.png", "02-overview-1280.png", "03-overview-768.png",
        "04-position-drift-1280.png", "05-backup-job-1280.png", "06-position-history-1280.png"})
    CHECK(fs::file_size(shots_dir() / f) > 5000);
}

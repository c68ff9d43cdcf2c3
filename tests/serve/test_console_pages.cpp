// The web console's HTML (lib/serve/console_pages.cpp), page by page from
// JSON shaped as the Service answers it: what each page shows to a viewer
// and to an operator, the forms and their CSRF field, text escaped, and the
// ages a person reads.
#include <catch2/catch.hpp>

#include "serve/console_pages.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_pages {

using namespace lmcfg;
using serve::Json;
namespace pages = serve::pages;

namespace {

// 2027-01-15T08:00:00Z
const serve::TimePoint kNow = serve::Clock::from_time_t(1'800'000'000);

bool has(const std::string& html, const std::string& part) {
  return html.find(part) != std::string::npos;
}

const serve::ConsoleUser kOperator{"night-shift", serve::Role::operator_, "C5RF"};
const serve::ConsoleUser kViewer{"grafana", serve::Role::viewer, "V1EW"};

fleet::LineEntry line1() {
  fleet::LineEntry l;
  l.name = "line1";
  l.port = "/dev/ttyUSB0";
  return l;
}

fleet::DriveEntry press3z() {
  fleet::DriveEntry d;
  d.name = "press3/z";
  d.id = 0x11;
  d.labels = {{"axis", "z <lift>"}};
  return d;
}

// Two revisions, newest first, as Service::history gives them.
Json history() {
  return Json::parse(R"([
    {"commit": "aaaaaaaaaa1111111111", "time": "2027-01-15T07:00:00Z", "author": "lmcfg serve",
     "message": "restore press3/z\n\nOperator: anna\nReason: new drive <after crash>\nTicket: T-7"},
    {"commit": "bbbbbbbbbb2222222222", "time": "2027-01-14T08:00:00Z", "author": "lmcfg serve",
     "message": "fleet backup: 0 changed, 0 unchanged, 2 new"}])");
}

}  // namespace

TEST_CASE("console pages: age from an ISO 8601 UTC time, past and future",
          "[serve][console_pages]") {
  CHECK(pages::age("2027-01-15T08:00:00Z", kNow) == "0 s ago");
  CHECK(pages::age("2027-01-15T07:59:01Z", kNow) == "59 s ago");
  CHECK(pages::age("2027-01-15T07:59:00Z", kNow) == "1 min ago");
  CHECK(pages::age("2027-01-15T07:00:01Z", kNow) == "59 min ago");
  CHECK(pages::age("2027-01-15T07:00:00Z", kNow) == "1 h 0 min ago");
  CHECK(pages::age("2027-01-14T08:00:01Z", kNow) == "23 h 59 min ago");
  CHECK(pages::age("2027-01-14T08:00:00Z", kNow) == "1 d 0 h ago");
  // 2026-11-24 17:20:15 to 2027-01-15 08:00:00: 52 days less 9 h 20 min 15 s.
  CHECK(pages::age("2026-11-24T17:20:15Z", kNow) == "51 d 14 h ago");
  // A deadline (a plan's expiry) is ahead.
  CHECK(pages::age("2027-01-15T08:00:30Z", kNow) == "in 30 s");
  CHECK(pages::age("2027-01-15T08:15:00Z", kNow) == "in 15 min");
  CHECK(pages::age("2027-01-15T09:01:00Z", kNow) == "in 1 h 1 min");
  // Not a UTC time as the service writes it: nothing rather than a wrong age.
  for (const std::string& bad :
       std::vector<std::string>{"", "yesterday", "2027-01-15 08:00:00Z", "2027-01-15T08:00:00",
                                "2027-01-15T08:00:00+02:00", "2027-01-15T08:00:00Zjunk"}) {
    INFO(bad);
    CHECK(pages::age(bad, kNow).empty());
  }
}

TEST_CASE(
    "console pages: shown_status says never backed up for an unknown position without "
    "a backup",
    "[serve][console_pages]") {
  CHECK(pages::shown_status(Json{{"status", "unknown"}, {"last_backup", nullptr}}) ==
        "never backed up");
  CHECK(pages::shown_status(Json{{"status", "unknown"}, {"last_backup", "2027-01-15T07:00:00Z"}}) ==
        "unknown");
  CHECK(pages::shown_status(Json{{"status", "drift"}, {"last_backup", nullptr}}) == "drift");
  CHECK(pages::shown_status(Json{{"status", "ok"}, {"last_backup", "2027-01-15T07:00:00Z"}}) ==
        "ok");
}

TEST_CASE("console pages: the sign-in page carries next and the CSRF value, escaped",
          "[serve][console_pages]") {
  const std::string html = pages::signin("", "/position?name=press3%2Fz&x=\"", "ABC123");
  CHECK(html.rfind("<!DOCTYPE html>\n<html lang=\"en\">", 0) == 0);
  CHECK(has(html, "<title>Sign in - lmcfg</title>"));
  CHECK(has(html, "<link rel=\"stylesheet\" href=\"/console.css\">"));
  CHECK(has(html, "<script src=\"/console.js\" defer></script>"));
  CHECK(has(html, "<input type=\"hidden\" name=\"csrf\" value=\"ABC123\">"));
  CHECK(has(
      html,
      "<input type=\"hidden\" name=\"next\" value=\"/position?name=press3%2Fz&amp;x=&quot;\">"));
  CHECK(has(html, "name=\"token\" type=\"password\""));
  CHECK_FALSE(has(html, "role=\"alert\""));
  CHECK_FALSE(has(html, "class=\"who\""));  // nobody is signed in
  const std::string refused = pages::signin("that token is not <known>", "/", "ABC123");
  CHECK(has(refused, "<p class=\"problem\" role=\"alert\">that token is not &lt;known&gt;</p>"));
}

TEST_CASE("console pages: the overview counts positions by status and filters the table",
          "[serve][console_pages]") {
  fleet::Inventory inv;
  inv.lines = {line1(), line1()};
  inv.lines[1].name = "line2";
  const Json drives = Json::parse(R"([
    {"name": "press3/z", "line": "line1", "id": 17, "status": "ok",
     "last_backup": "2027-01-15T07:00:00Z",
     "last_attempt": {"time": "2027-01-15T07:45:00Z", "job": "status", "result": "ok", "exit_code": 0},
     "differences": 0, "message": "matches the archive"},
    {"name": "press3/x", "line": "line1", "id": 18, "status": "drift",
     "last_backup": "2027-01-14T08:00:00Z", "last_attempt": null, "differences": 1,
     "message": "1 difference", "differing": ["0010h"]},
    {"name": "saw/a", "line": "line2", "id": 5, "status": "unknown", "last_backup": null,
     "last_attempt": null, "differences": 0, "message": ""}])");

  std::string html = pages::overview(kOperator, false, inv, drives, "", "", kNow);
  // As the console draws it: the summaries counted and filtered, the whole
  // state asked for of each row shown; the same page.
  Json summaries = Json::array();
  for (const auto& d : drives)
    summaries.push_back({{"name", d["name"]},
                         {"line", d["line"]},
                         {"id", d["id"]},
                         {"status", d["status"]},
                         {"last_backup", d["last_backup"]}});
  std::vector<std::string> asked;
  auto whole = [&](const Json& summary) {
    asked.push_back(summary["name"].get<std::string>());
    for (const auto& d : drives)
      if (d["name"] == summary["name"]) return d;
    return Json();
  };
  CHECK(pages::overview(kOperator, false, inv, summaries, "", "", kNow, 1, whole) == html);
  CHECK(asked == std::vector<std::string>{"press3/z", "press3/x", "saw/a"});
  asked.clear();
  CHECK(pages::overview(kOperator, false, inv, summaries, "line1", "drift", kNow, 1, whole) ==
        pages::overview(kOperator, false, inv, drives, "line1", "drift", kNow));
  CHECK(asked == std::vector<std::string>{"press3/x"});  // only the row shown
  CHECK(has(html, "<title>Plant overview - lmcfg</title>"));
  CHECK(has(html, "<span class=\"who\">night-shift (operator)</span>"));
  CHECK_FALSE(has(html, "Sign out"));  // without tokens there is no signing out
  CHECK(has(html, "<section id=\"live\" data-refresh=\"10\""));
  CHECK(has(html, "<li><strong>3</strong> positions</li>"));
  CHECK(has(html, "<strong data-count=\"ok\">1</strong>"));
  CHECK(has(html, "<strong data-count=\"drift\">1</strong>"));
  CHECK(has(html, "<strong data-count=\"failed\">0</strong>"));
  CHECK(has(html, "<strong data-count=\"unknown\">0</strong>"));
  CHECK(has(html, "<strong data-count=\"never backed up\">1</strong>"));
  CHECK(has(html,
            "As of <time class=\"abs\" datetime=\"2027-01-15T08:00:00Z\" "
            "title=\"2027-01-15T08:00:00Z\">2027-01-15T08:00:00Z</time>."));
  CHECK(has(html,
            "<tr data-drive=\"press3/z\" data-status=\"ok\"><td><a "
            "href=\"/position?name=press3%2Fz\"><span "
            "class=\"name\">press3/<wbr>z</span></a></td><td data-label=\"Line\">line1</td><td "
            "data-label=\"ID\">0x11</td><td><span class=\"status s-ok\">ok</span></td><td "
            "data-label=\"Last backup\"><time datetime=\"2027-01-15T07:00:00Z\" "
            "title=\"2027-01-15T07:00:00Z\">1 h 0 min ago</time></td><td data-label=\"Last "
            "event\">matches the archive <span class=\"muted\">(status, <time "
            "datetime=\"2027-01-15T07:45:00Z\" title=\"2027-01-15T07:45:00Z\">15 min "
            "ago</time>)</span></td></tr>"));
  CHECK(has(html,
            "<td data-label=\"ID\">0x05</td><td><span class=\"status s-never-backed-up\">never "
            "backed up</span></td><td data-label=\"Last backup\"><span "
            "class=\"muted\">never</span></td>"));
  CHECK(has(html, "<option value=\"line2\">line2</option>"));
  CHECK(has(html, "<option value=\"\" selected>all lines</option>"));

  html = pages::overview(kViewer, true, inv, drives, "line1", "drift", kNow);
  CHECK(has(html, "data-drive=\"press3/x\""));
  CHECK_FALSE(has(html, "data-drive=\"press3/z\""));
  CHECK_FALSE(has(html, "data-drive=\"saw/a\""));
  CHECK(has(html, "<strong>3</strong> positions"));  // the counts are the plant's, not the filter's
  CHECK(has(html, "<option value=\"line1\" selected>line1</option>"));
  CHECK(has(html, "<option value=\"drift\" selected>drift</option>"));
  // Signed in: the sign-out form with the user's CSRF value.
  CHECK(has(html,
            "<form method=\"post\" action=\"/signout\" class=\"inline\"><input "
            "type=\"hidden\" name=\"csrf\" value=\"V1EW\"><button type=\"submit\">Sign "
            "out</button></form>"));

  html = pages::overview(kViewer, true, inv, drives, "line2", "ok", kNow);
  CHECK_FALSE(has(html, "data-drive="));
  CHECK(
      has(html, "<tr><td colspan=\"6\" class=\"muted\">No position matches the filter.</td></tr>"));
  html = pages::overview(kViewer, true, inv, Json::array(), "", "", kNow);
  CHECK(has(html, "<li><strong>0</strong> positions</li>"));
  CHECK(has(html, "No position matches the filter."));
}

TEST_CASE("console pages: the overview shows 100 positions a page, the filter kept in its links",
          "[serve][console_pages]") {
  fleet::Inventory inv;
  inv.lines = {line1()};
  Json drives = Json::array();
  for (int i = 1; i <= 250; ++i)
    drives.push_back({{"name", "p/" + std::to_string(i)},
                      {"line", "line1"},
                      {"id", 17},
                      {"status", i % 2 ? "ok" : "drift"},
                      {"last_backup", "2027-01-15T07:00:00Z"},
                      {"last_attempt", nullptr},
                      {"differences", 0},
                      {"message", ""}});
  auto rows = [](const std::string& html) {
    std::size_t n = 0;
    for (auto at = html.find("<tr data-drive="); at != std::string::npos;
         at = html.find("<tr data-drive=", at + 1))
      ++n;
    return n;
  };
  std::string html = pages::overview(kViewer, true, inv, drives, "", "", kNow);
  CHECK(rows(html) == 100);
  CHECK(has(html, "<li><strong>250</strong> positions</li>"));  // the counts: every position
  CHECK(has(html, "data-drive=\"p/1\""));
  CHECK(has(html, "data-drive=\"p/100\""));
  CHECK_FALSE(has(html, "data-drive=\"p/101\""));
  CHECK(has(html,
            "<p>Positions 1-100 of 250 (page 1 of 3) &middot; <a "
            "href=\"/?line=&amp;status=&amp;page=2\">Next page</a></p>"));
  CHECK_FALSE(has(html, "Previous page"));

  html = pages::overview(kViewer, true, inv, drives, "", "", kNow, 3);
  CHECK(rows(html) == 50);
  CHECK(has(html, "data-drive=\"p/201\""));
  CHECK(has(html, "data-drive=\"p/250\""));
  CHECK(has(html,
            "<p>Positions 201-250 of 250 (page 3 of 3) &middot; <a "
            "href=\"/?line=&amp;status=&amp;page=2\">Previous page</a></p>"));

  // The filter counts its own matches: 125 in drift, the second page of them.
  html = pages::overview(kViewer, true, inv, drives, "line1", "drift", kNow, 2);
  CHECK(rows(html) == 25);
  CHECK(has(html, "data-drive=\"p/202\""));
  CHECK_FALSE(has(html, "data-drive=\"p/201\""));
  CHECK(has(html,
            "Positions 101-125 of 125 (page 2 of 2) &middot; <a "
            "href=\"/?line=line1&amp;status=drift&amp;page=1\">Previous page</a>"));

  // A page past the end says so and leads back to the last one.
  html = pages::overview(kViewer, true, inv, drives, "", "", kNow, 9);
  CHECK(rows(html) == 0);
  CHECK(has(html, "No position on this page."));
  CHECK(has(html, "href=\"/?line=&amp;status=&amp;page=3\">Previous page</a>"));
  // A plant of 100 positions or fewer has no page links.
  drives.erase(drives.begin() + 100, drives.end());
  CHECK_FALSE(has(pages::overview(kViewer, true, inv, drives, "", "", kNow), "class=\"pages\""));
}

TEST_CASE(
    "console pages: the overview's never-backed-up count agrees with the rows, a failure in "
    "words",
    "[serve][console_pages]") {
  fleet::Inventory inv;
  inv.lines = {line1()};
  // press3/z's first backup failed: its row says "Last backup: never".
  const Json drives = Json::parse(R"J([
    {"name": "press3/z", "line": "line1", "id": 17, "status": "failed", "last_backup": null,
     "last_attempt": {"time": "2027-01-15T07:45:00Z", "job": "backup", "result": "failed",
                      "exit_code": 4},
     "differences": 0,
     "message": "line 'line1' (/dev/ttyUSB0): no answer from drive 11h within 200.0 ms (main 05h sub 08h; raise --timeout-ms)"},
    {"name": "press3/x", "line": "line1", "id": 18, "status": "unknown", "last_backup": null,
     "last_attempt": null, "differences": 0, "message": "not read yet"}])J");
  std::string html = pages::overview(kOperator, false, inv, drives, "", "", kNow);
  CHECK(has(html, "<strong data-count=\"failed\">1</strong>"));
  CHECK(has(html, "<strong data-count=\"never backed up\">2</strong>"));
  CHECK(has(html, "<strong data-count=\"unknown\">0</strong>"));
  // The last event: what happened in words first, the service's message folded.
  CHECK(has(html,
            "<td data-label=\"Last event\"><details class=\"event\"><summary>The drive at "
            "press3/z did not answer.</summary>line &#39;line1&#39;"));
  // Filtering by "never backed up" shows both rows the count counts.
  html = pages::overview(kOperator, false, inv, drives, "", "never backed up", kNow);
  CHECK(has(html, "data-drive=\"press3/z\""));
  CHECK(has(html, "data-drive=\"press3/x\""));
}

TEST_CASE("console pages: a position's identity, state, actions by role and its history",
          "[serve][console_pages]") {
  const Json state = Json::parse(R"({"name": "press3/z", "line": "line1", "id": 17,
    "status": "drift", "last_backup": "2027-01-15T07:00:00Z", "last_attempt": null,
    "differences": 2, "message": "2 differences", "differing": ["0010h <a>", "0020h"]})");
  const std::string html =
      pages::position(kOperator, true, line1(), press3z(), state, Result<Json>(history()), kNow);
  CHECK(has(html, "<title>press3/z - lmcfg</title>"));
  CHECK(has(html, "<h1>press3/z <span class=\"status s-drift\">drift</span></h1>"));
  CHECK(has(html, "<dt>Line</dt><dd>line1 (/dev/ttyUSB0)</dd><dt>Drive ID</dt><dd>0x11</dd>"));
  CHECK(has(html, "<dt>axis</dt><dd>z &lt;lift&gt;</dd>"));
  CHECK(has(html, "<ul class=\"differing\"><li>0010h &lt;a&gt;</li><li>0020h</li></ul>"));
  CHECK(has(html, "<a href=\"/diff?name=press3%2Fz&amp;from=HEAD&amp;to=live\" id=\"live-diff\">"));
  // An operator's actions: back up (a POST with the CSRF value) and replace.
  CHECK(has(html,
            "<form method=\"post\" action=\"/backup\" class=\"inline\"><input "
            "type=\"hidden\" name=\"csrf\" value=\"C5RF\"><input type=\"hidden\" "
            "name=\"name\" value=\"press3/z\"><button type=\"submit\" id=\"backup-now\">"));
  CHECK(has(html, "href=\"/replace?name=press3%2Fz\">Replace the drive"));
  // The history: subject, author, the audit trailers, links per revision.
  CHECK(has(html,
            "<li data-commit=\"aaaaaaaaaa1111111111\"><time class=\"abs\" "
            "datetime=\"2027-01-15T07:00:00Z\" "
            "title=\"2027-01-15T07:00:00Z\">2027-01-15T07:00:00Z</time> "
            "<code>aaaaaaaaaa</code> <span class=\"subject\">restore press3/z</span>"));
  CHECK(has(html,
            "<dl class=\"trailers\"><dt>Operator</dt><dd>anna</dd><dt>Reason</dt><dd>new "
            "drive &lt;after crash&gt;</dd><dt>Ticket</dt><dd>T-7</dd></dl>"));
  CHECK(has(html,
            "<a href=\"/replace?name=press3%2Fz&amp;rev=bbbbbbbbbb2222222222\">restore "
            "this revision</a>"));
  // Compare: the older revision against the newer one by default.
  CHECK(has(html, "<option value=\"bbbbbbbbbb2222222222\" selected>"));
  CHECK(has(html,
            "<select id=\"d-to\" name=\"to\"><option value=\"aaaaaaaaaa1111111111\" "
            "selected>"));

  const std::string viewer =
      pages::position(kViewer, true, line1(), press3z(), state, Result<Json>(history()), kNow);
  CHECK_FALSE(has(viewer, "action=\"/backup\""));
  CHECK_FALSE(has(viewer, "restore this revision"));
  CHECK(has(viewer, "Signed in as a viewer: you can look at everything and change nothing."));
  CHECK(has(viewer, "diff with the drive</a>"));

  const std::string empty =
      pages::position(kViewer, true, line1(), press3z(), state, Result<Json>(Json::array()), kNow);
  CHECK(has(empty, "<p class=\"muted\">Not in the archive yet.</p>"));
  CHECK_FALSE(has(empty, "action=\"/diff\""));
  const std::string broken =
      pages::position(kViewer, true, line1(), press3z(), state,
                      Result<Json>(Error(Errc::io_error, "archive <locked>")), kNow);
  CHECK(has(broken, "<p class=\"problem\">archive &lt;locked&gt;</p>"));
}

TEST_CASE("console pages: the replace page offers the revisions to an operator only",
          "[serve][console_pages]") {
  std::string html =
      pages::replace(kOperator, true, line1(), press3z(), "", "", Result<Json>(history()));
  CHECK(has(html, "<title>Restore press3/z - lmcfg</title>"));
  CHECK(has(html,
            "on line <strong>line1</strong> (/dev/ttyUSB0) with drive ID "
            "<strong>0x11</strong>"));
  CHECK(has(html,
            "<form method=\"post\" action=\"/plan\" class=\"card\"><input type=\"hidden\" "
            "name=\"csrf\" value=\"C5RF\"><input type=\"hidden\" name=\"name\" "
            "value=\"press3/z\">"));
  // No revision asked for and none approved: the newest is chosen.
  CHECK(has(html,
            "<option value=\"aaaaaaaaaa1111111111\" selected>2027-01-15T07:00:00Z "
            "aaaaaaaaaa restore press3/z (newest)</option>"));
  CHECK(has(html, "<option value=\"bbbbbbbbbb2222222222\">"));
  // The approved revision is chosen, and marked.
  html = pages::replace(kOperator, true, line1(), press3z(), "", "bbbbbbbbbb2222222222",
                        Result<Json>(history()));
  CHECK(has(html,
            "<option value=\"aaaaaaaaaa1111111111\">2027-01-15T07:00:00Z aaaaaaaaaa "
            "restore press3/z (newest)</option>"));
  CHECK(has(html,
            "<option value=\"bbbbbbbbbb2222222222\" selected>2027-01-14T08:00:00Z "
            "bbbbbbbbbb fleet backup: 0 changed, 0 unchanged, 2 new (approved)</option>"));
  // A revision by its prefix.
  html = pages::replace(kOperator, true, line1(), press3z(), "bbbbbb", "", Result<Json>(history()));
  CHECK(has(html, "<option value=\"aaaaaaaaaa1111111111\">"));
  CHECK(has(html, "<option value=\"bbbbbbbbbb2222222222\" selected>"));

  html = pages::replace(kViewer, true, line1(), press3z(), "", "", Result<Json>(history()));
  CHECK(has(html, "Signed in as a viewer: planning and restoring need role operator."));
  CHECK_FALSE(has(html, "action=\"/plan\""));
  html = pages::replace(kOperator, true, line1(), press3z(), "", "", Result<Json>(Json::array()));
  CHECK(has(html,
            "<p class=\"problem\">the archive holds no file of press3/z yet: back it up "
            "first</p>"));
  CHECK_FALSE(has(html, "action=\"/plan\""));
  html = pages::replace(kOperator, true, line1(), press3z(), "", "",
                        Result<Json>(Error(Errc::io_error, "archive unreadable")));
  CHECK(has(html, "<p class=\"problem\">archive unreadable</p>"));
}

TEST_CASE("console pages: a job polls while it runs, shows its outcome in words and next step",
          "[serve][console_pages]") {
  Json running = Json::parse(R"({"id": "7", "kind": "restore", "scope": "drive press3/z",
    "state": "running", "who": "anna", "progress": {"done": 2, "total": 5,
    "step": "stop MC (\u00a713.3): the axis stops"}, "outcome": null, "message": "",
    "exit_code": null, "commit": null, "retry_of": null, "asked_by": null, "skipped": []})");
  std::string html = pages::job(kOperator, true, running, "press3/z");
  CHECK(has(html, "<h1>Restore of press3/z <span class=\"muted\">(job 7)</span></h1>"));
  CHECK(has(html, "<section id=\"live\" aria-live=\"polite\" data-refresh=\"1\">"));
  CHECK(has(html,
            "<strong class=\"job-state\" data-state=\"running\">running</strong>, asked by "
            "anna"));
  CHECK(has(html, "<progress max=\"5\" value=\"2\">2 of 5</progress> 2 of 5 step(s)"));
  // The step in words; the CLI's step folded below it.
  CHECK(has(html,
            "<p>Now: <span id=\"now\">Stopping motion control (the axis stops)</span></p><details "
            "class=\"cli\"><summary>As the command line says it</summary><pre>stop MC ("));
  CHECK_FALSE(has(html, "id=\"what-happened\""));

  Json failed = running;
  failed["state"] = "failed";
  failed["outcome"] = "failed after writing";
  failed["message"] = "timeout <no answer>";
  failed["exit_code"] = 4;
  failed["drive_state"] = "partially configured: some values were written, others not";
  failed["retry_pending"] = true;
  html = pages::job(kOperator, true, failed, "press3/z");
  CHECK(has(html, "<section id=\"live\" aria-live=\"polite\">"));
  CHECK(has(html,
            "<p class=\"problem\" role=\"alert\" id=\"what-happened\">The drive at press3/z "
            "stopped answering during the restore. The drive is partially configured: some "
            "values were written, others not.</p><p>What to check:</p><ol "
            "class=\"checklist\"><li>Is the drive powered?"));
  CHECK(has(html, "The service tries this restore again by itself when the drive answers"));
  CHECK(has(html,
            "<a class=\"button\" href=\"/replace?name=press3%2Fz\">Plan the restore "
            "again</a>"));
  // The CLI's words, folded: never the headline.
  CHECK(has(html,
            "<details class=\"cli\"><summary>As the command line says it</summary><p><code "
            "class=\"wrap\">failed after writing: timeout &lt;no answer&gt;</code></p><p>Exit "
            "code 4 (docs/cli.md).</p></details>"));
  CHECK_FALSE(has(html, "the CLI's exit code"));

  Json retry = failed;
  retry["retry_of"] = "5";
  retry["asked_by"] = "anna";
  retry["who"] = "lmcfg serve (automatic retry)";
  html = pages::job(kViewer, true, retry, "press3/z");
  CHECK(has(html, "<span id=\"retry-of\">automatic retry of job 5 (asked by anna)</span>"));
  CHECK_FALSE(has(html, "Plan the restore again"));  // a viewer's page has no actions

  Json done = running;
  done["state"] = "done";
  done["outcome"] = "restored and verified";
  done["exit_code"] = 0;
  done["commit"] = "cccccccccccccccc";
  html = pages::job(kOperator, true, done, "press3/z");
  CHECK(has(html,
            "<p class=\"verdict\" id=\"verdict\">Restored and verified: the drive reads back what "
            "was written.</p>"));
  CHECK(has(html, "<code id=\"commit\">cccccccccccccccc</code>"));
  CHECK_FALSE(has(html, "Plan the restore again"));
  CHECK_FALSE(has(html, "What stays different"));
  // After the write: the values the drive kept by policy, with why and what to do.
  Json kept = done;
  kept["kept"] =
      Json::parse(R"([{"kind": "parameter", "upid": "206C", "name": "MACID Source Select",
    "configuration": "3", "drive": "1", "reason": "a communication setting",
    "remedy": "Nothing needs doing while the drive answers on its line."}])");
  html = pages::job(kOperator, true, kept, "press3/z");
  CHECK(has(html,
            "was written.</p><section aria-labelledby=\"h-kept\"><h2 id=\"h-kept\">What stays "
            "different</h2><p>Not written, by policy: the drive keeps its own values here, and "
            "the position is ok with them.</p>"));
  CHECK(has(html,
            "<span class=\"pname\">MACID Source Select</span> <span class=\"muted "
            "id\">206Ch</span>: the configuration holds <span class=\"value\">3</span>, the "
            "drive keeps <span class=\"value\">1</span>."));

  // Values left out: amber, each listed, and what it means for the position.
  Json partial = done;
  partial["outcome"] = "restored except the listed values, verified";
  partial["exit_code"] = 7;
  partial["skipped"] = {"3010h Appl parameter: UPID does not exist on the target (\u00a710.3)"};
  html = pages::job(kOperator, true, partial, "press3/z");
  CHECK(has(html,
            "<div class=\"amber\" id=\"partial\"><p><strong>Restored, except 1 value(s) this "
            "drive cannot take.</strong>"));
  CHECK(has(html,
            "<ul id=\"skipped\"><li>3010h Appl parameter: UPID does not exist on the "
            "target</li></ul>"));

  Json backup = Json::parse(R"({"id": "3", "kind": "backup", "scope": "line line1",
    "state": "done", "who": null, "progress": {"done": 2, "total": 2, "step": ""},
    "outcome": "some drives failed", "message": "", "commit": "dddd", "drives": 2, "done": 2,
    "counts": {"unchanged": 1, "changed": 0, "new": 0, "failed": 1, "replaced": 0},
    "commits": ["dddd"], "errors": ["press3/x: timeout"]})");
  html = pages::job(kViewer, true, backup, "");
  CHECK_FALSE(has(html, "class=\"crumbs\""));  // no position named
  CHECK(has(html, "<strong class=\"job-state\" data-state=\"done\">finished</strong></p>"));
  CHECK(has(html, "2 of 2 drive(s)"));
  CHECK(has(html, "<li>unchanged <strong>1</strong></li>"));
  CHECK(has(html, "<p>Committed:</p><ul><li><code>dddd</code></li></ul>"));
  CHECK(has(html, "<p class=\"problem\">Errors:</p><ul><li>press3/x: timeout</li></ul>"));
  // A job that has not begun: an empty progress bar, not a division by zero.
  Json queued = backup;
  queued["state"] = "queued";
  queued["progress"] = {{"done", 0}, {"total", 0}, {"step", ""}};
  CHECK(has(pages::job(kViewer, true, queued, ""), "<progress max=\"1\" value=\"0\">0 of 0"));
}

TEST_CASE("console pages: an error page, with and without a user", "[serve][console_pages]") {
  std::string html = pages::error(&kOperator, true, "No <plan>", "no plan '0123' & more");
  CHECK(has(html, "<title>No &lt;plan&gt; - lmcfg</title>"));
  CHECK(has(html,
            "<h1>No &lt;plan&gt;</h1>\n<p class=\"problem\" role=\"alert\">no plan "
            "&#39;0123&#39; &amp; more</p>"));
  CHECK(has(html, "name=\"csrf\" value=\"C5RF\""));
  html = pages::error(nullptr, true, "Refused", "x");
  CHECK_FALSE(has(html, "class=\"who\""));
  CHECK_FALSE(has(html, "action=\"/signout\""));
}

TEST_CASE(
    "console pages: a failure in plain words, with a retry button and the CLI's message "
    "folded",
    "[serve][console_pages]") {
  const auto help = serve::words::help_for(
      lmcfg::Error(lmcfg::Errc::timeout, "no answer from drive 11h <within> 200.0 ms"), "press3/z");
  serve::RetryForm retry;
  retry.action = "/plan";
  retry.fields = {{"name", "press3/z"}, {"rev", "abc\"d"}};
  std::string html =
      pages::failure(&kOperator, true, "No plan", help,
                     "no answer from drive 11h <within> 200.0 ms", retry, "press3/z");
  CHECK(has(html,
            "<h1>No plan</h1>\n<p class=\"problem\" role=\"alert\" id=\"what-happened\">The "
            "drive at press3/z did not answer.</p>"));
  CHECK(has(html,
            "<form method=\"post\" action=\"/plan\" class=\"inline\"><input "
            "type=\"hidden\" name=\"csrf\" value=\"C5RF\"><input type=\"hidden\" "
            "name=\"name\" value=\"press3/z\"><input type=\"hidden\" name=\"rev\" "
            "value=\"abc&quot;d\"><button type=\"submit\" id=\"retry\">Try "
            "again</button></form>"));
  CHECK(has(html, "<a class=\"button\" href=\"/position?name=press3%2Fz\">Open the position</a>"));
  CHECK(has(html,
            "<summary>As the command line says it</summary><p><code class=\"wrap\">no "
            "answer from drive 11h &lt;within&gt; 200.0 ms</code></p></details>"));
  // Without a user (no form can carry a CSRF token): no button that posts.
  html = pages::failure(nullptr, true, "No plan", help, "x", retry, "");
  CHECK_FALSE(has(html, "id=\"retry\""));
}

}  // namespace serve_test_console_pages

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
  CHECK(has(html, "As of <time>2027-01-15T08:00:00Z</time>."));
  CHECK(has(html,
            "<tr data-drive=\"press3/z\" data-status=\"ok\"><td><a "
            "href=\"/position?name=press3%2Fz\">press3/z</a></td><td>line1</td><td>0x11</"
            "td><td><span class=\"status s-ok\">ok</span></td><td><time "
            "datetime=\"2027-01-15T07:00:00Z\" title=\"2027-01-15T07:00:00Z\">1 h 0 min "
            "ago</time></td><td>matches the archive <span class=\"muted\">(status, <time "
            "datetime=\"2027-01-15T07:45:00Z\" title=\"2027-01-15T07:45:00Z\">15 min "
            "ago</time>)</span></td></tr>"));
  CHECK(has(html,
            "<td>0x05</td><td><span class=\"status s-never-backed-up\">never backed "
            "up</span></td><td><span class=\"muted\">never</span></td>"));
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
            "<li data-commit=\"aaaaaaaaaa1111111111\"><time "
            "datetime=\"2027-01-15T07:00:00Z\">2027-01-15T07:00:00Z</time> "
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
      pages::replace(kOperator, true, line1(), press3z(), "", Result<Json>(history()));
  CHECK(has(html, "<title>Restore press3/z - lmcfg</title>"));
  CHECK(has(html,
            "on line <strong>line1</strong> (/dev/ttyUSB0) with drive ID "
            "<strong>0x11</strong>"));
  CHECK(has(html,
            "<form method=\"post\" action=\"/plan\" class=\"card\"><input type=\"hidden\" "
            "name=\"csrf\" value=\"C5RF\"><input type=\"hidden\" name=\"name\" "
            "value=\"press3/z\">"));
  // No revision asked for: the newest is chosen.
  CHECK(has(html,
            "<option value=\"aaaaaaaaaa1111111111\" selected>2027-01-15T07:00:00Z "
            "aaaaaaaaaa restore press3/z (newest)</option>"));
  CHECK(has(html, "<option value=\"bbbbbbbbbb2222222222\">"));
  // A revision by its prefix.
  html = pages::replace(kOperator, true, line1(), press3z(), "bbbbbb", Result<Json>(history()));
  CHECK(has(html, "<option value=\"aaaaaaaaaa1111111111\">"));
  CHECK(has(html, "<option value=\"bbbbbbbbbb2222222222\" selected>"));

  html = pages::replace(kViewer, true, line1(), press3z(), "", Result<Json>(history()));
  CHECK(has(html, "Signed in as a viewer: planning and restoring need role operator."));
  CHECK_FALSE(has(html, "action=\"/plan\""));
  html = pages::replace(kOperator, true, line1(), press3z(), "", Result<Json>(Json::array()));
  CHECK(has(html,
            "<p class=\"problem\">the archive holds no file of press3/z yet: back it up "
            "first</p>"));
  CHECK_FALSE(has(html, "action=\"/plan\""));
  html = pages::replace(kOperator, true, line1(), press3z(), "",
                        Result<Json>(Error(Errc::io_error, "archive unreadable")));
  CHECK(has(html, "<p class=\"problem\">archive unreadable</p>"));
}

TEST_CASE("console pages: a plan's steps, lists, and the confirm form by role and problems",
          "[serve][console_pages]") {
  Json p = Json::parse(R"({"plan_id": "0123abcd", "drive": "press3/z", "line": "line1",
    "id": "11h", "rev": "HEAD", "commit": "aaaaaaaaaa", "file": "press3/z.json", "who": "anna",
    "expires": "2027-01-15T08:15:00Z", "nothing_to_do": false,
    "steps": [
      {"kind": "write", "upid": "0010", "name": "Max Current", "old": "1.5", "new": "2",
       "unit": "A"},
      {"kind": "write", "upid": "0020", "name": "Mode", "old": null, "new": 3, "unit": ""},
      {"kind": "reset", "text": "reset the drive <to apply>"}],
    "losses": ["the curve 2 <lost>"], "notes": [], "problems": [], "incompatible": [],
    "factory_fresh": true})");
  std::string html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html, "<title>Plan for press3/z - lmcfg</title>"));
  CHECK(has(html,
            "A drive answers on line line1 as ID 11h. It is <strong "
            "id=\"factory-fresh\">factory-fresh</strong>"));
  CHECK(has(html,
            "This plan is valid until 2027-01-15T08:15:00Z (<time "
            "datetime=\"2027-01-15T08:15:00Z\" title=\"2027-01-15T08:15:00Z\">in 15 "
            "min</time>)"));
  CHECK(has(html,
            "<tr class=\"step\" data-kind=\"write\"><td>1</td><td>write</td><td><code>0010h"
            "</code> Max Current</td><td>1.5 A</td><td aria-hidden=\"true\">&rarr;</td><td>2 "
            "A</td></tr>"));
  CHECK(has(html,
            "<td><span class=\"muted\">none</span></td><td aria-hidden=\"true\">&rarr;</"
            "td><td>3</td>"));
  CHECK(has(html,
            "<td>3</td><td>reset</td><td colspan=\"4\">reset the drive &lt;to "
            "apply&gt;</td>"));
  CHECK(has(html, "<ul class=\"\" id=\"losses\"><li>the curve 2 &lt;lost&gt;</li></ul>"));
  CHECK_FALSE(has(html, "id=\"notes\""));  // an empty list is not shown
  CHECK_FALSE(has(html, "id=\"nothing-to-do\""));
  CHECK(has(html,
            "<form method=\"post\" action=\"/execute\" class=\"card\"><input "
            "type=\"hidden\" name=\"csrf\" value=\"C5RF\"><input type=\"hidden\" "
            "name=\"plan\" value=\"0123abcd\"><input type=\"hidden\" name=\"name\" "
            "value=\"press3/z\">"));
  CHECK_FALSE(has(html, "skip_incompatible"));

  // Values the drive cannot take: listed, and the form offers to skip them.
  p["incompatible"] = Json::parse(R"([{"upid": "0030", "message": "0030h: out of range"}])");
  p["factory_fresh"] = false;
  html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html, "<ul class=\"\" id=\"incompatible\"><li>0030h: out of range</li></ul>"));
  CHECK(has(html, "name=\"skip_incompatible\" value=\"1\""));
  CHECK(has(html, "<strong id=\"factory-fresh\">not factory-fresh</strong>"));

  CHECK_FALSE(has(pages::plan(kViewer, true, p, kNow), "action=\"/execute\""));
  CHECK(has(pages::plan(kViewer, true, p, kNow),
            "Signed in as a viewer: restoring needs role operator."));

  // Problems: refused, no form for anybody.
  p["problems"] = Json::parse(R"([{"kind": "plan", "message": "wrong drive <type>"}])");
  html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html, "<ul class=\"problem\" id=\"problems\"><li>wrong drive &lt;type&gt;</li></ul>"));
  CHECK(has(html, "This plan is refused"));
  CHECK(has(html, "<a href=\"/replace?name=press3%2Fz\">plan again</a>"));
  CHECK_FALSE(has(html, "action=\"/execute\""));

  p = Json::parse(R"({"plan_id": "00ff", "drive": "press3/z", "line": "line1", "id": "11h",
    "expires": "2027-01-15T08:15:00Z", "nothing_to_do": true, "steps": [], "losses": [],
    "notes": ["a note"], "problems": [], "incompatible": [], "factory_fresh": false})");
  html = pages::plan(kOperator, true, p, kNow);
  CHECK(
      has(html, "<p id=\"nothing-to-do\">Nothing to do: the drive already matches the file.</p>"));
  CHECK(has(html, "<ul class=\"muted\" id=\"notes\"><li>a note</li></ul>"));
}

TEST_CASE("console pages: a job polls while it runs, shows its outcome and next step",
          "[serve][console_pages]") {
  Json running = Json::parse(R"({"id": "7", "kind": "restore", "scope": "drive press3/z",
    "state": "running", "who": "anna", "progress": {"done": 2, "total": 5, "step": "write 0010h"},
    "outcome": null, "message": "", "exit_code": null, "commit": null})");
  std::string html = pages::job(kOperator, true, running, "press3/z");
  CHECK(has(html, "<h1>Job 7: restore of drive press3/z</h1>"));
  CHECK(has(html, "<section id=\"live\" aria-live=\"polite\" data-refresh=\"1\">"));
  CHECK(has(html,
            "<strong class=\"job-state\" data-state=\"running\">running</strong>, asked by "
            "anna"));
  CHECK(has(html, "<progress max=\"5\" value=\"2\">2 of 5</progress> 2 of 5 step(s)"));
  CHECK(has(html, "<p>Now: write 0010h</p>"));
  CHECK_FALSE(has(html, "id=\"outcome\""));

  Json failed = running;
  failed["state"] = "failed";
  failed["outcome"] = "failed";
  failed["message"] = "timeout <no answer>";
  failed["exit_code"] = 4;
  html = pages::job(kOperator, true, failed, "press3/z");
  CHECK(has(html, "<section id=\"live\" aria-live=\"polite\">"));
  CHECK(
      has(html, "<p class=\"problem\" id=\"outcome\">Outcome: failed (the CLI's exit code 4)</p>"));
  CHECK(has(html, "<p id=\"message\">timeout &lt;no answer&gt;</p>"));
  CHECK(has(html, "<a href=\"/replace?name=press3%2Fz\">plan again</a>"));

  Json done = running;
  done["state"] = "done";
  done["outcome"] = "restored and verified";
  done["exit_code"] = 0;
  done["commit"] = "cccccccccc";
  html = pages::job(kOperator, true, done, "press3/z");
  CHECK(has(html,
            "<p class=\"verdict\" id=\"outcome\">Outcome: restored and verified (the CLI's "
            "exit code 0)</p>"));
  CHECK(has(html, "<code id=\"commit\">cccccccccc</code>"));
  CHECK_FALSE(has(html, "plan again"));

  Json backup = Json::parse(R"({"id": "3", "kind": "backup", "scope": "line line1",
    "state": "done", "who": null, "progress": {"done": 2, "total": 2, "step": ""},
    "outcome": "some drives failed", "message": "", "commit": "dddd", "drives": 2, "done": 2,
    "counts": {"unchanged": 1, "changed": 0, "new": 0, "failed": 1, "replaced": 0},
    "commits": ["dddd"], "errors": ["press3/x: timeout"]})");
  html = pages::job(kViewer, true, backup, "");
  CHECK_FALSE(has(html, "class=\"crumbs\""));  // no position named
  CHECK(has(html, "<strong class=\"job-state\" data-state=\"done\">done</strong></p>"));
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

}  // namespace serve_test_console_pages

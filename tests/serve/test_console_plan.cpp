// The console's plan page (lib/serve/console_plan.cpp): the verdict first in
// plain words, each write with its name and values in units, refused plans
// without an active write button and with what resolves them, no internal
// step names or section signs outside the CLI's folded wording.
#include <catch2/catch.hpp>

#include "serve/console_pages.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_plan {

using namespace lmcfg;
using serve::Json;
namespace pages = serve::pages;

namespace {

const serve::TimePoint kNow = serve::Clock::from_time_t(1'800'000'000);  // 2027-01-15T08:00:00Z
const serve::ConsoleUser kOperator{"night-shift", serve::Role::operator_, "C5RF"};
const serve::ConsoleUser kViewer{"grafana", serve::Role::viewer, "V1EW"};

bool has(const std::string& html, const std::string& part) {
  return html.find(part) != std::string::npos;
}

// The text of the page without its folded CLI wording (tags removed): what a
// technician reads first.
std::string headline(const std::string& html) {
  const auto cli = html.find("<details class=\"cli\">");
  std::string text;
  bool in_tag = false;
  for (char c : cli == std::string::npos ? html : html.substr(0, cli)) {
    if (c == '<') in_tag = true;
    if (!in_tag) text += c;
    if (c == '>') in_tag = false;
  }
  return text;
}

Json plan() {
  return Json::parse(R"J({"plan_id": "0123abcd", "drive": "press3/z", "line": "line1",
    "id": "11h", "rev": "HEAD", "commit": "aaaaaaaaaa11", "file": "press3/z.json", "who": "anna",
    "expires": "2027-01-15T08:15:00Z", "nothing_to_do": false,
    "steps": [
      {"kind": "stop_mc", "text": "stop MC and application software (\u00a713.3)"},
      {"kind": "write_rom", "upid": "13A6", "name": "Maximal Current Set A", "old": "1.000 A",
       "new": "2.500 A", "unit": "A", "text": "write 13A6h"},
      {"kind": "write_rom", "upid": "0020", "name": "Mode <x>", "old": null, "new": "-3",
       "unit": "", "text": "write 0020h"},
      {"kind": "reset", "text": "reset the drive (\u00a713.1)"}],
    "losses": ["the curve 2 <lost>"], "notes": [], "problems": [], "incompatible": [],
    "factory_fresh": true})J");
}

}  // namespace

TEST_CASE("console plan: the verdict first, names and values in units, steps in words",
          "[serve][console_plan]") {
  const std::string html = pages::plan(kOperator, true, plan(), kNow);
  CHECK(has(html, "<title>Plan for press3/z - lmcfg</title>"));
  const auto verdict = html.find("id=\"verdict\"");
  REQUIRE(verdict != std::string::npos);
  CHECK(verdict < html.find("<table class=\"plan\">"));
  CHECK(has(html,
            "<p class=\"verdict\" id=\"verdict\">Will write 2 values. The axis stops during "
            "the restore. The drive restarts at the end.</p>"));
  CHECK(has(html,
            "with ID <span class=\"id\">11h</span>. It is <strong "
            "id=\"factory-fresh\">factory-fresh</strong>"));
  // The display already carries the unit: not said twice; the sign is kept.
  CHECK(has(html,
            "<td><span class=\"pname\">Maximal Current Set A</span> <span class=\"muted "
            "id\">13A6h</span></td><td><span class=\"value\">1.000 A</span></td><td "
            "aria-hidden=\"true\">&rarr;</td><td><span class=\"value\">2.500 A</span></td>"));
  CHECK(has(html,
            "<td><span class=\"muted\">not set</span></td><td "
            "aria-hidden=\"true\">&rarr;</td><td><span class=\"value\">-3</span></td>"));
  CHECK(has(html, "<span class=\"pname\">Mode &lt;x&gt;</span>"));
  CHECK(has(html,
            "<td colspan=\"4\">Stop motion control: the axis stops, and stays stopped until the "
            "restore ends</td>"));
  CHECK(has(html, "<ul class=\"\" id=\"losses\"><li>the curve 2 &lt;lost&gt;</li></ul>"));
  CHECK(has(html, "<time class=\"abs\" datetime=\"2027-01-15T08:15:00Z\""));
  // No internal step names or section signs before the CLI's folded wording.
  for (const char* internal : {"stop_mc", "write_rom", "\u00a7", "exit code"})
    CHECK_FALSE(has(headline(html), internal));
  CHECK(has(html,
            "<details class=\"cli\"><summary>As the command line says it</summary><pre>"
            "stop_mc: stop MC and application software ("));
  CHECK(has(html,
            "reset: reset the drive (\xc2\xa7"
            "13.1)\n</pre></details>"));
  CHECK(has(html,
            "<button type=\"submit\" class=\"danger\" id=\"execute\">Write to the "
            "drive</button>"));
  CHECK_FALSE(has(html, "skip_incompatible"));
}

TEST_CASE(
    "console plan: values the drive cannot take: the write needs the box, the page "
    "offers another revision",
    "[serve][console_plan]") {
  Json p = plan();
  p["incompatible"] = Json::parse(
      R"J([{"upid": "3010", "message": "3010h: UPID does not exist on the target (\u00a710.3)"}])J");
  const std::string html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html,
            "<p class=\"problem\" id=\"verdict\">Cannot be restored as it stands: this "
            "drive cannot take 1 value"));
  CHECK(has(html,
            "<ul class=\"\" id=\"incompatible\"><li>3010h: UPID does not exist on the "
            "target</li></ul>"));
  CHECK(has(html,
            "id=\"skip-incompatible\" required> Restore everything else, without the 1 "
            "value(s) listed above."));
  CHECK(has(html,
            "<button type=\"submit\" class=\"danger\" id=\"execute\" "
            "data-needs=\"skip-incompatible\">Write the rest to the drive</button>"));
  CHECK(has(html, "<a href=\"/replace?name=press3%2Fz\">choose another revision</a>"));
  CHECK(html.find("id=\"incompatible\"") < html.find("<table class=\"plan\">"));

  CHECK_FALSE(has(pages::plan(kViewer, true, p, kNow), "action=\"/execute\""));
  CHECK(has(pages::plan(kViewer, true, p, kNow),
            "Signed in as a viewer: restoring needs role operator."));
}

TEST_CASE("console plan: a refused plan has no write button and says what resolves it",
          "[serve][console_plan]") {
  Json p = plan();
  p["problems"] = Json::parse(R"([{"kind": "plan", "message": "wrong drive <type>"}])");
  const std::string html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html,
            "<p class=\"problem\" id=\"verdict\">Cannot be restored: 1 problem (below) "
            "must be resolved first. Nothing will be written.</p>"));
  CHECK(has(html, "<ul class=\"problem\" id=\"problems\"><li>wrong drive &lt;type&gt;</li></ul>"));
  CHECK_FALSE(has(html, "action=\"/execute\""));
  CHECK_FALSE(has(html, "id=\"execute\""));
  CHECK(has(html,
            "<a class=\"button\" href=\"/replace?name=press3%2Fz\">Choose another "
            "revision</a>"));
  CHECK(has(html,
            "<a class=\"button\" href=\"/diff?name=press3%2Fz&amp;from=HEAD&amp;to=live\">"
            "Read the drive now</a>"));

  p = Json::parse(R"({"plan_id": "00ff", "drive": "press3/z", "line": "line1", "id": "11h",
    "expires": "2027-01-15T08:15:00Z", "nothing_to_do": true, "steps": [], "losses": [],
    "notes": ["a note"], "problems": [], "incompatible": [], "factory_fresh": false})");
  const std::string nothing = pages::plan(kOperator, true, p, kNow);
  CHECK(has(nothing,
            "<p id=\"nothing-to-do\">Nothing to do: the drive already holds this "
            "configuration.</p>"));
  CHECK(has(nothing, "<ul class=\"muted\" id=\"notes\"><li>a note</li></ul>"));
}

}  // namespace serve_test_console_plan

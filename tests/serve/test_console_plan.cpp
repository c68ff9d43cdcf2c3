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
            "id\">13A6h</span></td><td data-label=\"Now (drive)\"><span class=\"value\">1.000 "
            "A</span></td><td aria-hidden=\"true\">&rarr;</td><td data-label=\"After "
            "(configuration)\"><span class=\"value\">2.500 A</span></td>"));
  CHECK(has(html,
            "<td data-label=\"Now (drive)\"><span class=\"muted\">not set</span></td><td "
            "aria-hidden=\"true\">&rarr;</td><td data-label=\"After (configuration)\"><span "
            "class=\"value\">-3</span></td>"));
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
  CHECK(has(nothing, "<ul class=\"muted\" id=\"notes\"><li>A note</li></ul>"));
}

TEST_CASE(
    "console plan: what stays different before the write, notes in words, an executed plan "
    "offers no write",
    "[serve][console_plan][matching]") {
  Json p = plan();
  p["kept"] = Json::parse(R"([{"kind": "parameter", "layer": "Intf", "upid": "2012",
    "name": "Baud Rate Parameter Def", "configuration": "16", "drive": "8",
    "by": "communication", "reason": "a communication setting: a restore keeps the drive's own value",
    "remedy": "Nothing needs doing while the drive answers on its line.",
    "text": "Intf 2012h Baud Rate Parameter Def: file 16, drive 8"}])");
  p["notes"] = Json::array(
      {"MC: the UPID database does not know the address usage of 9 parameter(s); asked the "
       "target for each (05h/03h, LinRS 3V27 p27) to check ROM write access",
       "leftover Appl 3020h = -1000 goes back to its default"});
  std::string html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html,
            "<p class=\"verdict\" id=\"verdict\">Will write 2 values. The axis stops during "
            "the restore. The drive restarts at the end. 1 value stays as the drive holds it "
            "(listed below).</p>"));
  CHECK(has(html,
            "<h2 id=\"h-kept\">What stays different</h2><p>The drive keeps these values of its "
            "own; they are not written, and the position is ok with them afterwards.</p><ul "
            "class=\"kept\" id=\"kept\"><li><span class=\"pname\">Baud Rate Parameter "
            "Def</span> <span class=\"muted id\">2012h</span>: the configuration holds <span "
            "class=\"value\">16</span>, the drive keeps <span class=\"value\">8</span>. <span "
            "class=\"muted\">Why: a communication setting: a restore keeps the drive&#39;s own "
            "value.</span></li></ul><p class=\"remedy\">Nothing needs doing while the drive "
            "answers on its line.</p>"));
  // The notes in a technician's words; the CLI's wording folded below them.
  for (const char* developer : {"UPID database", "05h/03h", "leftover", "address usage"})
    CHECK_FALSE(has(headline(html), developer));
  CHECK(has(html,
            "<li>The parameter list does not say whether some of these values can be stored on "
            "the drive, so the service asked the drive itself. Nothing to do.</li>"));
  CHECK(has(html,
            "<li>Appl 3020h = -1000 is not set by the configuration: it goes back to its "
            "factory setting.</li>"));
  CHECK(has(html, "<summary>The notes as the command line says them</summary><pre>MC: the UPID"));

  // Only kept values differ: nothing to write, and it says which stay.
  p["steps"] = Json::array();
  p["nothing_to_do"] = true;
  html = pages::plan(kOperator, true, p, kNow);
  CHECK(has(html,
            "<p class=\"verdict\" id=\"verdict\">Nothing to write: the drive holds this "
            "configuration, except values it keeps by policy. 1 value stays as the drive holds "
            "it (listed below).</p>"));
  CHECK(has(html,
            "<p id=\"nothing-to-do\">Nothing to do: the drive already holds this configuration, "
            "except the values it keeps (below).</p>"));

  // Reopened after it ran (Back): no write button, the job instead.
  p = plan();
  p["executed_job"] = "42";
  html = pages::plan(kOperator, true, p, kNow);
  CHECK_FALSE(has(html, "id=\"execute\""));
  CHECK_FALSE(has(html, "action=\"/execute\""));
  CHECK(has(html,
            "<p id=\"executed\">This plan was written to the drive already. <a "
            "class=\"button\" href=\"/job?id=42&amp;name=press3%2Fz\">See how it went</a>"));
}

}  // namespace serve_test_console_plan

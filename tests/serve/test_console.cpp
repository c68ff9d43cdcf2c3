// The web console of lmcfg serve over real HTTP on 127.0.0.1 (cpp-httplib's
// client, cookies by hand as a browser sends them): pages without tokens, the
// sign-in and its session cookie, the guard (no session, viewer, CSRF,
// expiry), and hostile names and labels rendered as text.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <map>
#include <regex>

#include "serve/console.hpp"
#include "serve/console_http.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console {

using namespace lmcfg;
using namespace std::chrono_literals;

namespace {

std::string csrf_of(const std::string& html) {
  std::smatch m;
  REQUIRE(std::regex_search(html, m, std::regex("name=\"csrf\" value=\"([0-9A-F]{64})\"")));
  return m[1];
}

// A browser's side: the cookies it was given (the session's and the sign-in
// form's), sent back with every request.
struct Browser {
  httplib::Client c;
  std::string cookie;                      // the session's
  std::map<std::string, std::string> jar;  // every cookie by name
  explicit Browser(int port) : c("127.0.0.1", port) {}
  httplib::Headers headers() const {
    std::string all;
    for (const auto& [k, v] : jar)
      if (!v.empty()) all += (all.empty() ? "" : "; ") + k + "=" + v;
    return all.empty() ? httplib::Headers{} : httplib::Headers{{"Cookie", all}};
  }
  httplib::Result keep(httplib::Result res) {
    if (!res) return res;
    for (std::size_t i = 0; i < res->get_header_value_count("Set-Cookie"); ++i) {
      const std::string set = res->get_header_value("Set-Cookie", i);
      const auto eq = set.find('='), semi = set.find(';');
      jar[set.substr(0, eq)] = set.substr(eq + 1, semi - eq - 1);
    }
    return res;
  }
  httplib::Result get(const std::string& path) { return keep(c.Get(path.c_str(), headers())); }
  httplib::Result post(const std::string& path, const httplib::Params& form) {
    return keep(c.Post(path.c_str(), headers(), form));
  }
  // Signs in with `token` through the sign-in form; the Set-Cookie header.
  std::string sign_in(const std::string& token) {
    auto page = get("/signin");
    REQUIRE(page);
    auto res = post("/signin", {{"csrf", csrf_of(page->body)}, {"token", token}, {"next", "/"}});
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location") == "/");
    const std::string set = res->get_header_value("Set-Cookie");
    std::smatch m;
    REQUIRE(std::regex_search(set, m, std::regex("^lmcfg_session=([0-9A-F]{64});")));
    cookie = m[1];
    return set;
  }
};

struct Tokens {
  std::string file, viewer, op;
  explicit Tokens(const std::filesystem::path& dir) : file((dir / "tokens").string()) {
    viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
    op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  }
  std::vector<serve::TokenEntry> load() const { return *serve::load_tokens(file); }
};

}  // namespace

TEST_CASE("console: without tokens no sign-in, pages with their CSP, a backup from the form",
          "[serve][console]") {
  test::Rig rig;
  rig.at(rig.now);
  test::Server server(*rig.service);
  Browser b(server.port);

  auto res = b.get("/");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "text/html; charset=utf-8");
  CHECK(res->get_header_value("Content-Security-Policy") ==
        "default-src 'none'; style-src 'self'; script-src 'self'; img-src 'self'; connect-src "
        "'self'; form-action 'self'; base-uri 'none'; frame-ancestors 'none'");
  CHECK(res->body.find("local (operator)") != std::string::npos);
  CHECK(res->body.find("Sign out") == std::string::npos);
  CHECK(res->body.find("<strong>2</strong> positions") != std::string::npos);
  CHECK(res->body.find("<strong data-count=\"ok\">2</strong>") != std::string::npos);
  CHECK(res->body.find("data-drive=\"press3/z\" data-status=\"ok\"") != std::string::npos);
  CHECK(b.get("/signin")->status == 303);

  // Filters are a GET form: the table holds only what matches.
  res = b.get("/?line=line1&status=drift");
  REQUIRE(res);
  CHECK(res->body.find("data-drive=") == std::string::npos);
  CHECK(res->body.find("No position matches the filter.") != std::string::npos);

  res = b.get("/position?name=press3%2Fz");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->body.find("<h1>press3/z <span class=\"status s-ok\">ok</span></h1>") !=
        std::string::npos);
  CHECK(res->body.find("<ol class=\"timeline\"><li data-commit=") != std::string::npos);
  const std::string csrf = csrf_of(res->body);

  // Even without sign-in a form needs the process's CSRF token: another site
  // cannot make a browser on this host post to the loopback console.
  res = b.post("/backup", {{"name", "press3/z"}});
  REQUIRE(res);
  CHECK(res->status == 403);
  CHECK(res->body.find("the form&#39;s CSRF token is missing or not this session&#39;s") !=
        std::string::npos);
  res = b.post("/backup", {{"name", "press3/z"}, {"csrf", csrf}});
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/job?id=3&name=press3/z");  // decoded by the client
  rig.service->wait_idle();
  res = b.get("/job?id=3&name=press3%2Fz");
  REQUIRE(res);
  CHECK(res->body.find("data-state=\"done\"") != std::string::npos);
  CHECK(res->body.find("data-refresh") == std::string::npos);  // done: no more polling

  // A revision's report and a diff with the drive: the report's own pages and CSP.
  res = b.get("/report?name=press3%2Fz&rev=HEAD");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Security-Policy") ==
        "default-src 'none'; style-src 'unsafe-inline'; frame-ancestors 'none'");
  CHECK(res->get_header_value_count("Content-Security-Policy") == 1);
  CHECK(res->body.find("<meta name=\"generator\" content=\"lmcfg report\">") != std::string::npos);
  CHECK(res->body.find("tr class=\"param") != std::string::npos);
  test::write_axis(rig.dir.path / "a.json", 0x11, "0010", 9);  // tuned on the drive
  res = b.get("/diff?name=press3%2Fz&from=HEAD&to=live");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->body.find("data-kind=\"parameter\" data-key=\"0010\"") != std::string::npos);
  CHECK(res->body.find("drive press3/z (live)") != std::string::npos);
  res = b.get("/report?name=press3%2Fz&rev=nosuchrev");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<h1>No report</h1>") != std::string::npos);

  res = b.get("/position?name=no/such");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("no drive named &#39;no/such&#39; in the inventory") != std::string::npos);

  res = b.get("/console.js");
  REQUIRE(res);
  CHECK(res->get_header_value("Content-Type") == "text/javascript; charset=utf-8");
  CHECK(res->body == serve::Console::script());
  CHECK(res->get_header_value("Cache-Control") == "max-age=300");
  CHECK(res->get_header_value_count("Cache-Control") == 1);
  res = b.get("/console.css");
  REQUIRE(res);
  CHECK(res->body == serve::Console::stylesheet());
}

TEST_CASE(
    "console: the guard: sign-in page without a session (API 401), viewer refused, "
    "CSRF checked, expiry, sign-out",
    "[serve][console]") {
  test::Rig rig;
  rig.at(rig.now);
  Tokens tokens(rig.dir.path);
  serve::TimePoint console_now = rig.now;
  serve::ConsoleOptions copt;
  copt.session_ttl = 1h;
  copt.clock = [&console_now] { return console_now; };
  test::Server server(*rig.service, tokens.load(), copt);
  Browser b(server.port);

  // No session: every page sends the browser to sign in, back to where it was.
  auto res = b.get("/position?name=press3%2Fz");
  REQUIRE(res);
  CHECK(res->status == 303);
  // (cpp-httplib's client decodes a Location once: on the wire it is
  // /signin?next=%2Fposition%3Fname%3Dpress3%252Fz)
  CHECK(res->get_header_value("Location") == "/signin?next=/position?name=press3%2Fz");
  res = b.get("/");
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/signin?next=/");
  res = b.get("/signin?next=%2Fposition%3Fname%3Dpress3%252Fz");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->body.find("name=\"token\" type=\"password\"") != std::string::npos);
  CHECK(res->body.find("name=\"next\" value=\"/position?name=press3%2Fz\"") != std::string::npos);
  // The API keeps its bearer tokens: a console cookie is no API credential.
  res = b.get("/api/v1/drives");
  REQUIRE(res);
  CHECK(res->status == 401);

  SECTION("a wrong token, a sign-in without the form's CSRF token, an outside next") {
    res = b.post("/signin", {{"csrf", csrf_of(b.get("/signin")->body)}, {"token", "not-a-token"}});
    REQUIRE(res);
    CHECK(res->status == 401);
    CHECK(res->body.find("that token is not in the tokens file") != std::string::npos);
    CHECK(b.jar.count("lmcfg_session") == 0);
    res = b.post("/signin", {{"token", tokens.op}});
    REQUIRE(res);
    CHECK(res->status == 403);
    CHECK(b.jar.count("lmcfg_session") == 0);
    res = b.post("/signin", {{"csrf", csrf_of(b.get("/signin")->body)},
                             {"token", tokens.op},
                             {"next", "//evil.example/"}});
    REQUIRE(res);
    CHECK(res->get_header_value("Location") == "/");
  }

  SECTION("a viewer sees everything and changes nothing") {
    const std::string set = b.sign_in(tokens.viewer);
    CHECK(set.find("; HttpOnly; SameSite=Strict; Path=/; Max-Age=3600") != std::string::npos);
    res = b.get("/position?name=press3%2Fz");
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->body.find("grafana (viewer)") != std::string::npos);
    CHECK(res->body.find("Back up now") == std::string::npos);
    CHECK(res->body.find("Signed in as a viewer") != std::string::npos);
    res = b.post("/backup", {{"name", "press3/z"}, {"csrf", csrf_of(res->body)}});
    REQUIRE(res);
    CHECK(res->status == 403);
    CHECK(res->body.find("&#39;grafana&#39; has role viewer: this needs role operator") !=
          std::string::npos);
    // Planning and executing too: refused before anything is read or written.
    const std::string csrf = csrf_of(b.get("/")->body);
    res = b.post("/plan", {{"name", "press3/z"}, {"rev", ""}, {"csrf", csrf}});
    REQUIRE(res);
    CHECK(res->status == 403);
    res = b.post("/execute", {{"plan", "0123abcd"}, {"reason", "r"}, {"csrf", csrf}});
    REQUIRE(res);
    CHECK(res->status == 403);
    CHECK(res->body.find("has role viewer: this needs role operator") != std::string::npos);
    res = b.get("/replace?name=press3%2Fz");
    REQUIRE(res);
    CHECK(res->body.find("planning and restoring need role operator") != std::string::npos);
    CHECK(res->body.find("action=\"/plan\"") == std::string::npos);
  }

  SECTION("an operator's form post needs its session's CSRF token") {
    b.sign_in(tokens.op);
    res = b.get("/position?name=press3%2Fz");
    REQUIRE(res);
    CHECK(res->body.find("night-shift (operator)") != std::string::npos);
    const std::string csrf = csrf_of(res->body);
    res = b.post("/backup", {{"name", "press3/z"}});
    REQUIRE(res);
    CHECK(res->status == 403);
    res = b.post("/backup", {{"name", "press3/z"}, {"csrf", std::string(64, '0')}});
    REQUIRE(res);
    CHECK(res->status == 403);
    // Another session's token is not this one's.
    Browser other(server.port);
    other.sign_in(tokens.op);
    res = other.post("/backup", {{"name", "press3/z"}, {"csrf", csrf}});
    REQUIRE(res);
    CHECK(res->status == 403);
    res = b.post("/backup", {{"name", "press3/z"}, {"csrf", csrf}});
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location").rfind("/job?id=", 0) == 0);
    rig.service->wait_idle();
  }

  SECTION("an expired session goes back to sign-in") {
    b.sign_in(tokens.op);
    console_now += 59min;
    CHECK(b.get("/")->status == 200);
    console_now += 1min;
    res = b.get("/");
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location") == "/signin?next=/");
  }

  SECTION("sign-out ends the session on the server, not only the cookie") {
    b.sign_in(tokens.op);
    const std::string csrf = csrf_of(b.get("/")->body);
    res = b.post("/signout", {{"csrf", csrf}});
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location") == "/signin");
    CHECK(res->get_header_value("Set-Cookie") ==
          "lmcfg_session=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0");
    CHECK(b.get("/")->status == 303);  // the old cookie, sent again, is refused
  }
}

TEST_CASE("console: hostile line names, labels and query text render as text", "[serve][console]") {
  const std::string hostile = "<script>alert(1)</script> & \\\"q\\\" 'x'";
  test::Rig rig(
      "", "", "\"" + hostile + "\"",
      "labels = { note = \"<img src=x onerror=alert(1)>\", \"a&b\" = \"\\\"quoted\\\"\" }\n");
  rig.at(rig.now);
  test::Server server(*rig.service);
  Browser b(server.port);
  const std::string escaped =
      "&lt;script&gt;alert(1)&lt;/script&gt; &amp; &quot;q&quot; &#39;x&#39;";

  auto res = b.get("/");
  REQUIRE(res);
  CHECK(res->body.find("<script>alert") == std::string::npos);
  CHECK(res->body.find("<td data-label=\"Line\">" + escaped + "</td>") != std::string::npos);
  CHECK(res->body.find("<option value=\"" + escaped + "\">" + escaped + "</option>") !=
        std::string::npos);

  res = b.get("/position?name=press3%2Fz");
  REQUIRE(res);
  CHECK(res->body.find("<img") == std::string::npos);
  CHECK(res->body.find("<dt>note</dt><dd>&lt;img src=x onerror=alert(1)&gt;</dd>") !=
        std::string::npos);
  CHECK(res->body.find("<dt>a&amp;b</dt><dd>&quot;quoted&quot;</dd>") != std::string::npos);

  res = b.get("/position?name=%3Cscript%3Ealert(1)%3C%2Fscript%3E");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<script>alert") == std::string::npos);
  CHECK(res->body.find("no drive named &#39;&lt;script&gt;alert(1)&lt;/script&gt;&#39;") !=
        std::string::npos);
  // The filter's value is echoed into the form, escaped.
  res = b.get("/?line=%22%3E%3Cscript%3E");
  REQUIRE(res);
  CHECK(res->body.find("\"><script>") == std::string::npos);
}

TEST_CASE(
    "console: a plan with no drive answering shows the error as the CLI says it, "
    "nothing planned",
    "[serve][console]") {
  test::Rig rig;
  rig.at(rig.now);
  test::Server server(*rig.service);
  Browser b(server.port);
  const std::string csrf = csrf_of(b.get("/replace?name=press3%2Fx")->body);
  test::write_axis(rig.dir.path / "b.json", 0x13);  // no drive answers as 12h any more
  auto res = b.post("/plan", {{"name", "press3/x"}, {"rev", "HEAD"}, {"csrf", csrf}});
  REQUIRE(res);
  INFO(res->body);
  CHECK(res->status == 502);  // the link or the drive failed, not the console
  CHECK(res->get_header_value("Location").empty());
  CHECK(res->body.find("<h1>No plan</h1>") != std::string::npos);
  CHECK(res->body.find("class=\"problem\" role=\"alert\"") != std::string::npos);
  res = b.post("/execute", {{"plan", "0123abcd"}, {"reason", "r"}, {"csrf", csrf}});
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("no plan &#39;0123abcd&#39;") != std::string::npos);
}

TEST_CASE(
    "console: an operator approves a revision from the position's history, and without a reason "
    "nothing is approved",
    "[serve][console][git-cli]") {
  test::Rig rig;
  rig.at(rig.now);
  test::write_axis(rig.dir.path / "b.json", 0x12, "0010", 7);
  rig.at(rig.now + 6h);  // a used spare's configuration archived: still drift
  const std::string spare = test::git(rig.dir.path / "archive", "rev-parse HEAD").substr(0, 40);
  test::Server server(*rig.service);
  Browser b(server.port);
  auto page = b.get("/position?name=press3%2Fx");
  REQUIRE(page);
  const std::string& html = page->body;
  CHECK(html.find("Differences at the last check (each as the approved configuration &rarr; "
                  "the drive):") != std::string::npos);
  CHECK(html.find("<p id=\"approved\">Approved configuration: <code>") != std::string::npos);
  // The commissioned revision is marked, the spare's backup can be approved.
  CHECK(html.find("This is the approved configuration.") != std::string::npos);
  CHECK(html.find("<input type=\"hidden\" name=\"rev\" value=\"" + spare + "\">") !=
        std::string::npos);
  CHECK(html.find("Approve this revision</button>") != std::string::npos);
  const std::string csrf = csrf_of(html);

  auto res = b.post("/approve", {{"name", "press3/x"}, {"rev", spare}, {"csrf", csrf}});
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(res->body.find("<h1>Not approved</h1>") != std::string::npos);
  CHECK(res->body.find("approving press3/x needs a reason") != std::string::npos);
  CHECK((*rig.service->drive("press3/x"))["status"] == "drift");
  // A form's text may carry line breaks; a reason may not.
  res = b.post("/approve", {{"name", "press3/x"},
                            {"rev", spare},
                            {"reason", "ok\r\nOperator: mallory"},
                            {"csrf", csrf}});
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(res->body.find("<h1>Not approved</h1>") != std::string::npos);
  CHECK(res->body.find("reason contains a control character (0x0D at offset 2): give one line "
                       "without control characters") != std::string::npos);

  res = b.post("/approve", {{"name", "press3/x"},
                            {"rev", spare},
                            {"reason", "spare accepted"},
                            {"ticket", "CHG-9"},
                            {"csrf", csrf}});
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/position?name=press3/x");  // decoded by the client
  rig.service->wait_idle();
  const auto x = *rig.service->drive("press3/x");
  CHECK(x["status"] == "ok");
  CHECK(x["approved"]["rev"] == spare);
  CHECK(x["approved"]["who"] == "local");
  CHECK(x["approved"]["ticket"] == "CHG-9");
}

}  // namespace serve_test_console

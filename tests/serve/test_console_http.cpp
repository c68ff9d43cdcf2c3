// The console's routes (lib/serve/console_http.cpp) on a bare cpp-httplib
// server of their own (no REST API beside them), over real HTTP on
// 127.0.0.1: the headers of every answer, the session cookie found among
// others, where sign-in sends the browser back to (never another host), the
// redirect after every form, and failures as pages with their status.
#include <httplib.h>

#include <catch2/catch.hpp>
#include <regex>

#include "raw_http.hpp"
#include "serve/console.hpp"
#include "serve/console_http.hpp"
#include "serve/tokens.hpp"
#include "serve_rig.hpp"
#include "web/web_router.hpp"
#include "web/web_server.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace serve_test_console_http {

using namespace lmcfg;
using namespace lmcfg::test;
using namespace std::chrono_literals;

namespace {

// register_console_routes on a router and server of their own, on 127.0.0.1, any port.
struct ConsoleServer {
  web::Router router;
  std::unique_ptr<web::Server> server;
  std::unique_ptr<serve::Console> console;
  std::thread thread;
  int port = 0;
  ConsoleServer(serve::Service& s, std::optional<std::vector<serve::TokenEntry>> tokens,
                serve::ConsoleOptions opt = {}) {
    auto c = serve::Console::create(s, std::move(tokens), std::move(opt));
    REQUIRE(c.ok());
    console = std::move(c).value();
    serve::register_console_routes(router, *console);
    web::ServerOptions so;
    so.handle = [this](web::Request& req, web::Response& res) {
      if (router.dispatch(req, res) != web::Router::Outcome::handled) res.status = 404;
    };
    server = std::make_unique<web::Server>(std::move(so));
    auto p = server->bind("127.0.0.1", 0);
    REQUIRE(p.ok());
    port = *p;
    thread = std::thread([this] { server->serve(); });
  }
  ~ConsoleServer() {
    server->stop();
    thread.join();
  }
};

// A fresh sign-in form: its CSRF value and the cookie that goes with it.
struct SigninForm {
  std::string csrf;
  httplib::Headers cookie;
};
SigninForm signin_form(httplib::Client& c) {
  auto res = c.Get("/signin");
  REQUIRE(res);
  REQUIRE(res->status == 200);
  const std::string set = res->get_header_value("Set-Cookie");
  std::smatch m;
  REQUIRE(std::regex_match(set, m,
                           std::regex("lmcfg_signin=([0-9A-F]{64}); HttpOnly; SameSite=Strict; "
                                      "Path=/signin; Max-Age=600")));
  return {m[1], {{"Cookie", "lmcfg_signin=" + std::string(m[1])}}};
}

httplib::Headers with_cookie(const std::string& cookie) { return {{"Cookie", cookie}}; }

// The security headers every console answer has, each once.
void check_headers(const httplib::Response& res, const std::string& cache = "no-store") {
  CHECK(res.get_header_value("Content-Security-Policy") ==
        std::string(serve::Console::content_security_policy()));
  CHECK(res.get_header_value_count("Content-Security-Policy") == 1);
  CHECK(res.get_header_value("X-Content-Type-Options") == "nosniff");
  CHECK(res.get_header_value("Referrer-Policy") == "no-referrer");
  CHECK(res.get_header_value("Cache-Control") == cache);
  CHECK(res.get_header_value_count("Cache-Control") == 1);
}

}  // namespace

TEST_CASE("console http: assets, favicon and pages with their headers, without tokens",
          "[serve][console_http]") {
  Rig rig;
  ConsoleServer s(*rig.service, std::nullopt);
  httplib::Client c("127.0.0.1", s.port);

  auto res = c.Get("/console.css");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "text/css; charset=utf-8");
  CHECK(res->body == serve::Console::stylesheet());
  check_headers(*res, "max-age=300");
  res = c.Get("/console.js");
  REQUIRE(res);
  CHECK(res->get_header_value("Content-Type") == "text/javascript; charset=utf-8");
  check_headers(*res, "max-age=300");
  res = c.Get("/favicon.ico");
  REQUIRE(res);
  CHECK(res->status == 204);
  CHECK(res->body.empty());
  check_headers(*res);

  res = c.Get("/");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Type") == "text/html; charset=utf-8");
  check_headers(*res);
  CHECK(res->get_header_value("Set-Cookie").empty());  // no sign-in, no session

  // Without tokens there is nothing to sign in to: back to the console (or next).
  res = c.Get("/signin?next=%2Fposition");
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/");
  res = c.Post("/signin", "next=%2Fjob%3Fid%3D1", "application/x-www-form-urlencoded");
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/job?id=1");
  check_headers(*res);

  // A page of a position not in the inventory: the 404 page, with the headers.
  res = c.Get("/position?name=press9%2Fq");
  REQUIRE(res);
  CHECK(res->status == 404);
  check_headers(*res);
  CHECK(res->body.find("<h1>No such position</h1>") != std::string::npos);
  res = c.Get("/plan?id=0123abcd");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("no plan &#39;0123abcd&#39; (executed already, or made too long ago)") !=
        std::string::npos);
  res = c.Get("/job?id=999");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<h1>No such job</h1>") != std::string::npos);
}

TEST_CASE("console http: the session cookie is found among others, by its exact name",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  ConsoleServer s(*rig.service, *serve::load_tokens(file));
  auto session = s.console->sign_in(op);
  REQUIRE(session.ok());
  const std::string id = session->id;
  httplib::Client c("127.0.0.1", s.port);

  for (const std::string& cookie : std::vector<std::string>{
           "lmcfg_session=" + id, "theme=dark; lmcfg_session=" + id,
           "theme=dark;lmcfg_session=" + id + "; lang=de", "a=1;   lmcfg_session=" + id}) {
    INFO(cookie);
    auto res = c.Get("/", with_cookie(cookie));
    REQUIRE(res);
    CHECK(res->status == 200);
    CHECK(res->body.find("night-shift (operator)") != std::string::npos);
  }
  for (const std::string& cookie : std::vector<std::string>{
           std::string(), "lmcfg_session=", "lmcfg_sessionx=" + id, "xlmcfg_session=" + id,
           "lmcfg_session " + id, "lmcfg_session=" + id + "0", "other=lmcfg_session=" + id}) {
    INFO(cookie);
    auto res = c.Get("/", with_cookie(cookie));
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location") == "/signin?next=/");
  }
}

TEST_CASE("console http: sign-in sends the browser back to a path of this console only",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  serve::ConsoleOptions copt;
  copt.session_ttl = 2h;
  ConsoleServer s(*rig.service, *serve::load_tokens(file), copt);
  httplib::Client c("127.0.0.1", s.port);

  // A page asked for without a session: sign in, then back to it with its query.
  auto res = c.Get("/job?name=press3%2Fz&id=3");
  REQUIRE(res);
  CHECK(res->status == 303);
  // (the client decodes the Location once: on the wire the next is encoded again)
  CHECK(res->get_header_value("Location") == "/signin?next=/job?id=3&name=press3%2Fz");
  // A form posted without a session goes back to the overview.
  res = c.Post("/backup", "name=press3%2Fz", "application/x-www-form-urlencoded");
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/signin?next=/");

  res = c.Get("/signin?next=%2Fposition%3Fname%3Dpress3%252Fz");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->body.find("name=\"next\" value=\"/position?name=press3%2Fz\"") != std::string::npos);
  for (const std::string& next : std::vector<std::string>{
           "//evil.example/", "/\\evil.example", "https://evil.example/", "evil", "", "/ /x"}) {
    INFO("next=" << next);
    res = c.Get(("/signin?next=" + serve::url_encode(next)).c_str());
    REQUIRE(res);
    CHECK(res->body.find("name=\"next\" value=\"/\"") != std::string::npos);
  }

  // A tab or line break in a query is refused at the edge (400) ...
  for (const std::string& next : std::vector<std::string>{"/\t/evil.example", "/\n/evil.example"}) {
    res = c.Get(("/signin?next=" + serve::url_encode(next)).c_str());
    REQUIRE(res);
    CHECK(res->status == 400);
  }
  // ... and through the form (where tabs pass the edge) it leads to the console, not off-site.
  for (const std::string& next : std::vector<std::string>{"/\\evil.example", "/\t/evil.example"}) {
    auto f = signin_form(c);
    res = c.Post("/signin", f.cookie,
                 httplib::Params{{"csrf", f.csrf}, {"token", op}, {"next", next}});
    REQUIRE(res);
    CHECK(res->status == 303);
    CHECK(res->get_header_value("Location") == "/");
  }
  auto f = signin_form(c);
  res =
      c.Post("/signin", f.cookie, httplib::Params{{"csrf", f.csrf}, {"token", op}, {"next", "/"}});
  const std::string set = res->get_header_value("Set-Cookie");
  CHECK(std::regex_match(
      set, std::regex("lmcfg_session=[0-9A-F]{64}; HttpOnly; SameSite=Strict; Path=/; "
                      "Max-Age=7200")));
  f = signin_form(c);
  res = c.Post(
      "/signin", f.cookie,
      httplib::Params{{"csrf", f.csrf}, {"token", op}, {"next", "/position?name=press3%2Fz"}});
  REQUIRE(res);
  CHECK(res->get_header_value("Location") == "/position?name=press3/z");  // decoded by the client
}

TEST_CASE("console http: the sign-in form's CSRF value is the visitor's own, used once",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  ConsoleServer s(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", s.port);
  auto refused = [&](const httplib::Headers& cookie, const std::string& csrf) {
    auto res = c.Post("/signin", cookie, httplib::Params{{"csrf", csrf}, {"token", op}});
    REQUIRE(res);
    CHECK(res->status == 403);
    CHECK(res->body.find("the form is out of date: sign in again") != std::string::npos);
    // a fresh form, never a session
    CHECK(res->get_header_value("Set-Cookie").rfind("lmcfg_signin=", 0) == 0);
    check_headers(*res);
  };
  const SigninForm a = signin_form(c), b = signin_form(c);
  CHECK(a.csrf != b.csrf);
  // A reload (or a second tab) with the cookie keeps the form that is open valid.
  auto again = c.Get("/signin", a.cookie);
  REQUIRE(again);
  CHECK(again->body.find(a.csrf) != std::string::npos);
  refused({}, a.csrf);        // no cookie
  refused(a.cookie, b.csrf);  // another visitor's value
  refused({{"Cookie", "lmcfg_signin=" + std::string(64, 'A')}},
          std::string(64, 'A'));  // not issued
  auto res = c.Post("/signin", a.cookie,
                    httplib::Params{{"csrf", a.csrf}, {"token", std::string(64, '0')}});
  REQUIRE(res);
  CHECK(res->status == 401);
  CHECK(res->body.find("that token is not in the tokens file") != std::string::npos);
  CHECK(res->get_header_value("Set-Cookie").rfind("lmcfg_signin=", 0) == 0);
  refused(a.cookie, a.csrf);  // used once already
  res = c.Post("/signin", b.cookie, httplib::Params{{"csrf", b.csrf}, {"token", op}});
  REQUIRE(res);
  CHECK(res->status == 303);
  // A form that is not a form, or not UTF-8.
  res = c.Post("/signin", "csrf=x", "text/plain");
  REQUIRE(res);
  CHECK(res->status == 415);
  res = c.Post("/signin", "csrf=%FF", "application/x-www-form-urlencoded");
  REQUIRE(res);
  CHECK(res->status == 400);
  CHECK(res->body.find("the form&#39;s field &#39;csrf=%FF&#39; is malformed, not valid UTF-8 or "
                       "has a control character") != std::string::npos);
}

TEST_CASE("console http: sessions are bounded per token, no one's sign-ins end another's session",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  std::vector<std::string> viewers;
  for (int i = 1; i <= 5; ++i)
    viewers.push_back(*serve::add_token(file, "screen-" + std::to_string(i), serve::Role::viewer));
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  serve::ConsoleOptions copt;
  copt.clock = [&] { return now; };
  auto console = serve::Console::create(*rig.service, *serve::load_tokens(file), copt);
  REQUIRE(console.ok());
  auto sign_in = [&](const std::string& token) {
    now += 1s;
    auto session = (*console)->sign_in(token);
    REQUIRE(session.ok());
    return session->id;
  };
  auto alive = [&](const std::vector<std::string>& ids) {
    return std::count_if(ids.begin(), ids.end(),
                         [&](const std::string& id) { return (*console)->user(id).has_value(); });
  };
  const std::string operator_session = sign_in(op);
  // 260 sign-ins with one viewer token: that token keeps its newest 64, the
  // operator's session (older than all of them) lives on.
  std::vector<std::string> first;
  for (int i = 0; i < 260; ++i) first.push_back(sign_in(viewers[0]));
  CHECK((*console)->user(operator_session)->who == "night-shift");
  CHECK(alive(first) == static_cast<long>(serve::Console::kMaxSessionsPerToken));
  CHECK_FALSE((*console)->user(first[260 - 65]).has_value());
  CHECK((*console)->user(first[260 - 64]).has_value());
  // Four more tokens fill the pool (256); beyond it the token holding the
  // most makes room, never the operator's one session.
  std::vector<std::string> all = first;
  for (std::size_t v = 1; v < viewers.size(); ++v)
    for (int i = 0; i < 64; ++i) all.push_back(sign_in(viewers[v]));
  CHECK((*console)->user(operator_session).has_value());
  CHECK(alive(all) + 1 == static_cast<long>(serve::Console::kMaxSessions));
  // The 255 viewer sessions end up shared nearly evenly (50 to 52 a token),
  // each token keeping its newest: the first token its last 50.
  CHECK(alive(first) == 50);
  CHECK_FALSE((*console)->user(first[260 - 51]).has_value());
  CHECK((*console)->user(first[260 - 50]).has_value());
  CHECK((*console)->user(all.back()).has_value());
}

TEST_CASE("console http: sign-in values are bounded per address, one address pushes out its own",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto op = *serve::add_token(file, "night-shift", serve::Role::operator_);
  ConsoleServer s(*rig.service, *serve::load_tokens(file));
  httplib::Client c("127.0.0.1", s.port);
  const SigninForm waiting = signin_form(c);  // a user with the form open
  // 300 anonymous GET /signin from another address ...
  std::string flood_first, flood_last;
  for (int i = 0; i < 300; ++i) {
    RawClient flood(s.port, "127.0.0.2");
    REQUIRE(flood.send("GET /signin HTTP/1.1\r\nHost: 127.0.0.1:" + std::to_string(s.port) +
                       "\r\nConnection: close\r\n\r\n"));
    const std::string answer = flood.response(2000);
    REQUIRE(answer.rfind("HTTP/1.1 200 OK\r\n", 0) == 0);
    std::smatch m;
    REQUIRE(std::regex_search(answer, m, std::regex("lmcfg_signin=([0-9A-F]{64});")));
    (i == 0 ? flood_first : flood_last) = m[1];
  }
  // ... leave the waiting user's value valid: the submit signs in.
  auto res =
      c.Post("/signin", waiting.cookie, httplib::Params{{"csrf", waiting.csrf}, {"token", op}});
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Set-Cookie").rfind("lmcfg_session=", 0) == 0);
  // The flood's own oldest went (32 kept per address), its newest is valid.
  CHECK_FALSE(s.console->signin_nonce_ok(flood_first, flood_first));
  CHECK(s.console->signin_nonce_ok(flood_last, flood_last));
}

TEST_CASE("console: the sign-in pool makes room from the address holding the most",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  (void)*serve::add_token(file, "night-shift", serve::Role::operator_);
  serve::TimePoint now = serve::Clock::from_time_t(1'800'000'000);
  serve::ConsoleOptions copt;
  copt.clock = [&] { return now; };
  auto console = serve::Console::create(*rig.service, *serve::load_tokens(file), copt);
  REQUIRE(console.ok());
  auto& c = **console;
  const std::string mine = *c.signin_nonce({}, "10.0.0.1");
  const std::string yours = *c.signin_nonce({}, "10.0.0.2");
  // 20 addresses of 32 values each: 640 issued, 256 kept, the two single
  // values older than all of them among those kept.
  std::vector<std::string> flood;
  for (int a = 0; a < 20; ++a)
    for (int i = 0; i < 32; ++i) {
      now += 100ms;
      flood.push_back(*c.signin_nonce({}, "10.1.0." + std::to_string(a)));
    }
  CHECK(c.signin_nonce_ok(mine, mine));
  CHECK(c.signin_nonce_ok(yours, yours));
  CHECK(std::count_if(flood.begin(), flood.end(), [&](const std::string& v) {
          return c.signin_nonce_ok(v, v);
        }) == static_cast<long>(serve::Console::kSigninNonces) - 2);
  // A value still shows again for its cookie, from any address.
  const std::string again = *c.signin_nonce({}, "10.0.0.3");
  CHECK(*c.signin_nonce(again, "10.0.0.4") == again);
  // Expired ones go: 10 minutes.
  now += std::chrono::minutes(10);
  CHECK_FALSE(c.signin_nonce_ok(again, again));
}

TEST_CASE("console http: forms answer with a redirect, failures as pages with their status",
          "[serve][console_http]") {
  Rig rig;
  rig.at(rig.now);
  ConsoleServer s(*rig.service, std::nullopt);
  httplib::Client c("127.0.0.1", s.port);
  const std::string csrf = s.console->anonymous_csrf();

  auto res = c.Post("/backup", httplib::Params{{"csrf", csrf}, {"name", "press3/z"}});
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->body.empty());
  check_headers(*res);
  const std::string location = res->get_header_value("Location");
  CHECK(std::regex_match(location, std::regex("/job\\?id=[0-9]+&name=press3/z")));
  rig.service->wait_idle();
  res = c.Get(location.substr(0, location.find("&name")).c_str());
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->body.find("data-state=\"done\"") != std::string::npos);

  res = c.Post("/backup", httplib::Params{{"csrf", csrf}, {"name", "press9/q"}});
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->get_header_value("Location").empty());
  CHECK(res->body.find("<h1>Cannot back up</h1>") != std::string::npos);
  CHECK(res->body.find("no drive named &#39;press9/q&#39; in the inventory") != std::string::npos);
  res = c.Post("/plan", httplib::Params{{"csrf", csrf}, {"name", "press9/q"}, {"rev", ""}});
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<h1>No plan</h1>") != std::string::npos);
  res = c.Post(
      "/execute",
      httplib::Params{
          {"csrf", csrf}, {"plan", "0123abcd"}, {"reason", "r"}, {"skip_incompatible", "1"}});
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<h1>Not restored</h1>") != std::string::npos);
  CHECK(res->body.find("no plan &#39;0123abcd&#39;") != std::string::npos);

  // The report's pages: the report's own policy; a failure is a console page.
  res = c.Get("/report?name=press3%2Fz&rev=HEAD");
  REQUIRE(res);
  CHECK(res->status == 200);
  CHECK(res->get_header_value("Content-Security-Policy") ==
        std::string(serve::Console::report_security_policy()));
  CHECK(res->get_header_value_count("Content-Security-Policy") == 1);
  CHECK(res->get_header_value("Cache-Control") == "no-store");
  res = c.Get("/diff?name=press3%2Fz&from=nosuchrev&to=HEAD");
  REQUIRE(res);
  CHECK(res->status == 404);
  CHECK(res->body.find("<h1>No diff</h1>") != std::string::npos);
  check_headers(*res);
}

TEST_CASE("console http: sign-out needs the session's CSRF value and clears the cookie",
          "[serve][console_http]") {
  Rig rig;
  const std::string file = (rig.dir.path / "tokens").string();
  const auto viewer = *serve::add_token(file, "grafana", serve::Role::viewer);
  ConsoleServer s(*rig.service, *serve::load_tokens(file));
  auto session = s.console->sign_in(viewer);
  REQUIRE(session.ok());
  httplib::Client c("127.0.0.1", s.port);
  const auto cookie = with_cookie("lmcfg_session=" + session->id);

  auto res = c.Post("/signout", cookie, httplib::Params{{"csrf", s.console->anonymous_csrf()}});
  REQUIRE(res);
  CHECK(res->status == 403);
  CHECK(res->body.find("the form&#39;s CSRF token is missing or not this session&#39;s") !=
        std::string::npos);
  CHECK(s.console->user(session->id).has_value());  // still signed in

  // A viewer may sign out (it changes nothing on the plant).
  res = c.Post("/signout", cookie, httplib::Params{{"csrf", session->user.csrf}});
  REQUIRE(res);
  CHECK(res->status == 303);
  CHECK(res->get_header_value("Location") == "/signin");
  CHECK(res->get_header_value("Set-Cookie") ==
        "lmcfg_session=; HttpOnly; SameSite=Strict; Path=/; Max-Age=0");
  CHECK_FALSE(s.console->user(session->id).has_value());
}

}  // namespace serve_test_console_http

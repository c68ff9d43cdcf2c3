// lmcfg serve's routes (lib/web/web_router.cpp): placeholders without
// regular expressions, first match wins, 404 and 405 with the methods allowed.
#include <catch2/catch.hpp>

#include "web/web_router.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace web_test_web_router {

using namespace lmcfg::web;

TEST_CASE("web router: placeholders match as the routes need them", "[web][web_router]") {
  std::vector<std::string> g;
  CHECK(match_pattern("/api/v1/drives", "/api/v1/drives", g));
  CHECK(g == std::vector<std::string>{"/api/v1/drives"});
  CHECK_FALSE(match_pattern("/api/v1/drives", "/api/v1/drives/", g));
  CHECK(match_pattern("/api/v1/drives/{any}/history", "/api/v1/drives/press3/z/history", g));
  CHECK(g == std::vector<std::string>{"/api/v1/drives/press3/z/history", "press3/z"});
  // The longest name first: a drive named "a/history" has a history too.
  CHECK(match_pattern("/d/{any}/history", "/d/a/history/history", g));
  CHECK(g.at(1) == "a/history");
  CHECK_FALSE(match_pattern("/d/{any}/history", "/d/history", g));
  CHECK_FALSE(match_pattern("/d/{any}", "/d/", g));
  CHECK(match_pattern("/p/{hex}/execute", "/p/0a9f/execute", g));
  CHECK_FALSE(match_pattern("/p/{hex}/execute", "/p/0A9F/execute", g));
  CHECK(match_pattern("/jobs/{num}", "/jobs/12", g));
  CHECK_FALSE(match_pattern("/jobs/{num}", "/jobs/12a", g));
  // A long path costs time in its length, not stack: no regular expression.
  const std::string long_name(8000, 'x');
  CHECK(match_pattern("/d/{any}/history", "/d/" + long_name + "/history", g));
  CHECK(g.at(1) == long_name);
  CHECK_FALSE(match_pattern("/d/{any}/history", "/d/" + long_name, g));
}

TEST_CASE("web router: first match, HEAD as GET, 404 and 405", "[web][web_router]") {
  Router r;
  std::string ran;
  r.Get("/d/{any}/history", [&](const Request& q, Response&) { ran = "history " + q.matches[1]; });
  r.Get("/d/{any}", [&](const Request& q, Response&) { ran = "drive " + q.matches[1]; });
  r.Post("/d/{any}/backup", [&](const Request& q, Response&) { ran = "backup " + q.matches[1]; });
  Request q;
  Response res;
  q.method = "GET";
  q.path = "/d/a/b/history";
  CHECK(r.dispatch(q, res) == Router::Outcome::handled);
  CHECK(ran == "history a/b");
  q.method = "HEAD";
  q.path = "/d/a";
  CHECK(r.dispatch(q, res) == Router::Outcome::handled);
  CHECK(ran == "drive a");
  q.method = "POST";
  q.path = "/d/a/backup";
  CHECK(r.dispatch(q, res) == Router::Outcome::handled);
  CHECK(ran == "backup a");
  q.path = "/d/a";
  std::string allow;
  CHECK(r.dispatch(q, res, &allow) == Router::Outcome::method_not_allowed);
  CHECK(allow == "GET");
  q.path = "/other";
  CHECK(r.dispatch(q, res) == Router::Outcome::not_found);
}

}  // namespace web_test_web_router

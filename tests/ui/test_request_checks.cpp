// The Host and Origin checks lmcfg serve and lmcfg ui share
// (serve/request_checks.hpp).
#include <catch2/catch.hpp>

#include "serve/request_checks.hpp"

namespace ui_test_request_checks {

using namespace lmcfg;
using namespace lmcfg::serve;

web::Request request(const std::string& method,
                     std::vector<std::pair<std::string, std::string>> h) {
  web::Request r;
  r.method = method;
  for (auto& [k, v] : h) r.headers.emplace(k, v);
  return r;
}

TEST_CASE("request checks: only the server's own Host names", "[request_checks]") {
  const std::vector<std::string> hosts{"127.0.0.1:8470", "localhost:8470"};
  CHECK_FALSE(check_host(request("GET", {{"Host", "127.0.0.1:8470"}}), hosts));
  CHECK_FALSE(check_host(request("GET", {{"Host", "LOCALHOST:8470"}}), hosts));
  auto r = check_host(request("GET", {{"Host", "evil.example:8470"}}), hosts);
  REQUIRE(r);
  CHECK(r->status == 421);
  CHECK(r->message.rfind("the Host header 'evil.example:8470' is not this service's address "
                         "(127.0.0.1:8470)",
                         0) == 0);
  CHECK(check_host(request("GET", {}), hosts));
}

TEST_CASE("request checks: a state-changing request from another site is refused",
          "[request_checks]") {
  CHECK_FALSE(check_origin(request("GET", {{"Sec-Fetch-Site", "cross-site"}})));
  CHECK_FALSE(check_origin(request("POST", {{"Sec-Fetch-Site", "same-origin"}})));
  CHECK_FALSE(check_origin(request("POST", {})));  // curl, scripts
  CHECK_FALSE(
      check_origin(request("POST", {{"Host", "127.0.0.1:1"}, {"Origin", "http://127.0.0.1:1"}})));
  auto site = check_origin(request("POST", {{"Sec-Fetch-Site", "cross-site"}}));
  REQUIRE(site);
  CHECK(site->status == 403);
  CHECK(site->message ==
        "cross-site request refused: Sec-Fetch-Site is 'cross-site', a state-changing request "
        "must come from this service's own pages");
  auto origin =
      check_origin(request("POST", {{"Host", "127.0.0.1:1"}, {"Origin", "http://evil.example"}}));
  REQUIRE(origin);
  CHECK(origin->message ==
        "cross-origin request refused: Origin 'http://evil.example' is not this service's origin "
        "'http://127.0.0.1:1'");
  CHECK(safe_method("HEAD"));
  CHECK_FALSE(safe_method("DELETE"));
}

}  // namespace ui_test_request_checks

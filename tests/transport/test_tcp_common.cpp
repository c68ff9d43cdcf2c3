// The platform-neutral half of the TCP client (lib/transport/tcp_common.cpp):
// a destination's checks and name, and the waits' deadline arithmetic, the
// same in the POSIX and the Windows build.
#include <catch2/catch.hpp>

#include "transport/tcp_common.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace transport_test_tcp_common {

using namespace lmcfg;
using namespace lmcfg::transport;
using namespace std::chrono_literals;

TEST_CASE("tcp common: a destination is named as messages name it, bad ones refused",
          "[tcp_common]") {
  auto v4 = detail::tcp_target("10.0.0.5", 4001, "tcp");
  REQUIRE(v4.ok());
  CHECK(v4->name == "10.0.0.5");
  CHECK(v4->where == "10.0.0.5:4001");
  for (const char* host : {"::1", "[::1]"}) {
    auto v6 = detail::tcp_target(host, 4001, "rfc2217");
    REQUIRE(v6.ok());
    CHECK(v6->name == "::1");
    CHECK(v6->where == "[::1]:4001");
  }
  auto port0 = detail::tcp_target("127.0.0.1", 0, "tcp");
  REQUIRE_FALSE(port0.ok());
  CHECK(port0.error().code == make_error_code(Errc::invalid_argument));
  CHECK(port0.error().message == "tcp 127.0.0.1:0: port 0 is not a valid port");
  auto empty = detail::tcp_target("", 4001, "rfc2217");
  REQUIRE_FALSE(empty.ok());
  CHECK(empty.error().message == "rfc2217: host is empty");
}

TEST_CASE("tcp common: the time left to a deadline rounds up and stops at 0", "[tcp_common]") {
  const auto now = Clock::now();
  CHECK(detail::ms_left(now - 5ms) == 0);
  const int left = detail::ms_left(now + 1500us + 10s);
  CHECK(left >= 10001);
  CHECK(left <= 10002);
  CHECK(detail::ms_left(now + std::chrono::hours(24 * 365)) == 1'000'000'000);
}

}  // namespace transport_test_tcp_common

#include <catch2/catch.hpp>

#include "ops/audit.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_audit {

using lmcfg::ops::Audit;
using lmcfg::ops::trailers;

TEST_CASE("audit trailers name who, why and the ticket, one line each", "[audit]") {
  CHECK(trailers(Audit{"alice", "spare after fault F12", "INC-4711"}) ==
        "Operator: alice\nReason: spare after fault F12\nTicket: INC-4711\n");
  CHECK(trailers(Audit{"svc-token", "", ""}) == "Operator: svc-token\n");
  CHECK(trailers(Audit{}) == "");
  CHECK(trailers(Audit{"bob", "two\nlines\r\n", ""}) == "Operator: bob\nReason: two lines  \n");
}

}  // namespace ops_test_audit

// What a restore plan's LinRS parameters select after the drive's reset
// (ops::expected_link): the MACID and baud rate "By Parameter" (LinRS §15),
// and why each is known or not.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "e2e_support.hpp"
#include "ops/expected_link.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_expected_link {

using namespace lmcfg;

TEST_CASE("relink: what the restored LinRS parameters select, and why", "[relink]") {
  auto db = test::built_database();
  REQUIRE(db);
  ops::Plan plan;
  plan.expected.scope.layers = {false, false, true, false};
  auto& intf = plan.expected.layer(3);
  intf = {config::Parameter{0x200E, 2, std::nullopt, std::nullopt, {}, {}, {}},
          config::Parameter{0x2012, 8, std::nullopt, std::nullopt, {}, {}, {}},
          config::Parameter{0x206C, 3, std::nullopt, std::nullopt, {}, {}, {}},
          config::Parameter{0x2076, 0x22, std::nullopt, std::nullopt, {}, {}, {}}};
  auto e = ops::expected_link(plan, *db);
  CHECK(e.baud == 38400u);
  CHECK(e.macid == std::uint8_t{0x22});
  REQUIRE(e.reasons.size() == 2);
  CHECK(e.reasons[0] == "MACID 22h: 206Ch = By Parameter, 2076h MACID Parameter Value = 34");
  CHECK(e.reasons[1] == "baud rate 38400: 200Eh = By Parameter, 2012h Baud Rate Parameter Def = 8");
  // Each setting's own reason, for a message about that setting alone.
  CHECK(e.macid_reason == e.reasons[0]);
  CHECK(e.baud_reason == e.reasons[1]);

  // 2076h absent: its database default 11h. 2012h = 16: a code the seeds do not give.
  intf = {config::Parameter{0x200E, 2, std::nullopt, std::nullopt, {}, {}, {}},
          config::Parameter{0x2012, 16, std::nullopt, std::nullopt, {}, {}, {}},
          config::Parameter{0x206C, 3, std::nullopt, std::nullopt, {}, {}, {}}};
  e = ops::expected_link(plan, *db);
  CHECK(e.macid == std::uint8_t{0x11});
  CHECK(e.reasons[0] ==
        "MACID 11h: 206Ch = By Parameter, 2076h MACID Parameter Value = 17 (its default)");
  CHECK_FALSE(e.baud);
  CHECK(e.reasons[1] ==
        "baud rate: 200Eh = By Parameter, but the database has no rate for 2012h = 16 (seed 003 "
        "states only 8 = 38400 Baud)");

  // Nothing in the file: factory defaults, the hex switches.
  intf.clear();
  e = ops::expected_link(plan, *db);
  CHECK_FALSE(e.baud);
  CHECK_FALSE(e.macid);
  CHECK(e.reasons[0].find("factory default, the hex switches") != std::string::npos);
  CHECK(e.macid_reason == e.reasons[0]);
}

TEST_CASE("relink: without a database the settings' own reasons follow the database's",
          "[relink]") {
  ops::Plan plan;
  plan.expected.scope.layers = {false, false, true, false};
  plan.expected.layer(3) = {
      config::Parameter{0x206C, 3, std::nullopt, std::nullopt, {}, {}, {}},
      config::Parameter{0x2076, 0x22, std::nullopt, std::nullopt, {}, {}, {}}};
  const auto e = ops::expected_link(plan, db::Database::empty());
  REQUIRE(e.reasons.size() == 3);
  CHECK(e.reasons[0] ==
        "no UPID database: the factory defaults of the LinRS parameters are unknown");
  CHECK(e.macid == std::uint8_t{0x22});
  CHECK(e.macid_reason == "MACID 22h: 206Ch = By Parameter, 2076h MACID Parameter Value = 34");
  CHECK(e.reasons[1] == e.macid_reason);
  CHECK_FALSE(e.baud);
  CHECK(e.reasons[2] == e.baud_reason);
  CHECK(e.baud_reason.rfind("baud rate: 200Eh", 0) == 0);
}

}  // namespace ops_test_expected_link

#include <catch2/catch.hpp>

#include "config/config_io.hpp"
#include "config/json_io.hpp"
#include "config/migrate.hpp"
#include "config/xml_io.hpp"
#include "test_config_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_migrate {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::testing;

namespace {
DriveConfig expected_from_v1() {
  DriveConfig c = golden_sinrise();
  c.identity.tool_version = "0.0.9";
  c.identity.captured_at = "2023-06-01T08:30:00Z";
  c.identity.labels.clear();
  c.layer(1).push_back(param(0x0005, 0xFFFFFFFF));  // -1 -> two's complement
  return c;
}
}  // namespace

TEST_CASE("config: version 1 files are migrated to the current version", "[config]") {
  for (const char* name : {"v1-sinrise.json", "v1-sinrise.xml"}) {
    INFO(name);
    auto r = read_config_file(fixture_dir() / name);
    INFO((r.ok() ? std::string() : r.error().message));
    REQUIRE(r.ok());
    CHECK(*r == expected_from_v1());
    CHECK(r->scope == Scope{});  // v1 captured modified parameters of every layer, curves and CT
    // Written again, it is a version 3 file.
    auto j = write_json(*r);
    REQUIRE(j.ok());
    CHECK(j->find("\"format_version\": 3") != std::string::npos);
    CHECK(*read_json(*j, "j") == *r);
  }
}

TEST_CASE("config: migrate_v1_to_v2 step by step", "[config]") {
  ConfigV1 v1;
  v1.baud = "115200";
  v1.params = {{0x3001, -2, "f: p1"}, {0x1000, 4294967295LL, "f: p2"}, {0x0001, 7, "f: p3"}};
  v1.ct_entries = {{3, {}, hex("01 02"), "f: e1"}};
  auto r = migrate_v1_to_v2(v1);
  REQUIRE(r.ok());
  CHECK(r->identity.link.baud == "115200");
  CHECK(r->layer(4).at(0).value == 0xFFFFFFFEu);
  CHECK(r->layer(2).at(0).value == 0xFFFFFFFFu);
  CHECK(r->layer(1).at(0).upid == 1);
  CHECK(r->ct_entries.at(0).raw == hex("01 02"));

  v1.field_sep = "/@";
  v1.params = {{0x0F00, 1, "f: /lmcfg/parameters/param[1]"}};
  CHECK(migrate_v1_to_v2(v1).error().message ==
        "f: /lmcfg/parameters/param[1]/@upid: UPID 3840 (0F00h) is in no layer's range (0000-0EFF, "
        "1000-1EFF, 2000-2EFF, 3000-3EFF)");
  v1.params = {{1, 1, "f: a"}, {1, 2, "f: b"}};
  CHECK(migrate_v1_to_v2(v1).error().message == "f: b/@upid: duplicate UPID 1 (0001h)");
  v1.params = {{1, 4294967296LL, "f: a"}};
  CHECK(migrate_v1_to_v2(v1).error().message ==
        "f: a/@value: expected a 32-bit value (-2147483648..4294967295), found 4294967296");
  v1.params = {{1, -2147483649LL, "f: a"}};
  CHECK_FALSE(migrate_v1_to_v2(v1).ok());
  v1.params.clear();
  v1.ct_entries = {{256, {}, hex("01"), "f: e"}};
  CHECK(migrate_v1_to_v2(v1).error().message ==
        "f: e/@id: command table entry ID 256 is outside 0..255");
  v1.ct_entries.clear();
  v1.curves = {
      {1, hex("08 00 03 00 02 00 04 00"), hex("00 00 00 00"), "f: /lmcfg/curves/curve[1]"}};
  auto bad = migrate_v1_to_v2(v1);
  REQUIRE_FALSE(bad.ok());
  CHECK(bad.error().code == make_error_code(Errc::validation_failed));
  CHECK(
      bad.error().message ==
      "f: /lmcfg/curves/curve[1]/@data: curve 1: data block has 4 bytes but the info block says 2 "
      "setpoints x 4 bytes = 8");
}

TEST_CASE("config: version 1 errors carry v1 locations", "[config]") {
  const std::string j =
      "{\"format\": \"lmcfg-drive-config\", \"format_version\": 1,\n"
      " \"parameters\": [\n"
      "  {\"upid\": 5026, \"value\": 1},\n"
      "  {\"upid\": 61440, \"value\": 1}\n"
      " ]}\n";
  auto r = read_json(j, "old.json");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().message ==
        "old.json:4:3: /parameters/1/upid: UPID 61440 (F000h) is in no layer's range (0000-0EFF, "
        "1000-1EFF, 2000-2EFF, 3000-3EFF)");
  const std::string x =
      "<lmcfg format=\"lmcfg-drive-config\" format_version=\"1\"><parameters>"
      "<param upid=\"5026\" value=\"1\"/><param upid=\"5026\" value=\"x\"/></parameters></lmcfg>";
  auto rx = read_xml(x, "old.xml");
  REQUIRE_FALSE(rx.ok());
  CHECK(rx.error().message ==
        "old.xml: /lmcfg/parameters/param[2]/@value: expected a decimal value, found \"x\"");
  const std::string x2 =
      "<lmcfg format=\"lmcfg-drive-config\" format_version=\"1\"><parameters>"
      "<param upid=\"5026\" value=\"1\"/><param upid=\"5026\" value=\"2\"/></parameters></lmcfg>";
  CHECK(read_xml(x2, "old.xml").error().message ==
        "old.xml: /lmcfg/parameters/param[2]/@upid: duplicate UPID 5026 (13A2h)");
}

TEST_CASE("config: format version checks", "[config]") {
  auto r = read_json("{\"format\": \"lmcfg-drive-config\", \"format_version\": 4}", "new.json");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == make_error_code(Errc::unsupported_version));
  CHECK(r.error().message ==
        "new.json: file format_version 4 is newer than this lmcfg supports (3); update lmcfg");
  auto r0 = read_json("{\"format\": \"lmcfg-drive-config\", \"format_version\": 0}", "z.json");
  CHECK(r0.error().message ==
        "z.json:1:52: /format_version: expected format_version 1..3, found 0");
  auto x = read_xml("<lmcfg format=\"lmcfg-drive-config\" format_version=\"7\"/>", "new.xml");
  CHECK(x.error().message ==
        "new.xml: file format_version 7 is newer than this lmcfg supports (3); update lmcfg");
}

}  // namespace config_test_migrate

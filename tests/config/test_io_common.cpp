// The text forms both readers and writers share (lib/config/io_common.cpp):
// UPIDs as 4 hex digits, byte rows of at most 16 bytes, decimals without
// sign or leading zeros, DeviceNet motors and command IDs, and the format
// checks (docs/config-files.md).
#include <catch2/catch.hpp>

#include "config/io_common.hpp"
#include "config/model.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace config_test_io_common {

using namespace lmcfg;
using namespace lmcfg::config;
using namespace lmcfg::config::detail;

TEST_CASE("io_common: UPIDs are written as 4 upper-case hex digits, read in either case",
          "[config][io_common]") {
  CHECK(upid_hex(0x13A2) == "13A2");
  CHECK(upid_hex(0x0001) == "0001");
  CHECK(upid_hex(0xFFFF) == "FFFF");
  CHECK(parse_upid_hex("13a2") == std::optional<std::uint16_t>(0x13A2));
  CHECK(parse_upid_hex("20C7") == std::optional<std::uint16_t>(0x20C7));
  CHECK_FALSE(parse_upid_hex("13A"));
  CHECK_FALSE(parse_upid_hex("013A2"));
  CHECK_FALSE(parse_upid_hex("0x13"));
  CHECK_FALSE(parse_upid_hex("13G2"));
  CHECK_FALSE(parse_upid_hex(""));
}

TEST_CASE("io_common: byte rows hold 16 bytes, the last one the rest", "[config][io_common]") {
  Bytes b;
  for (unsigned i = 0; i < 18; ++i) b.push_back(static_cast<std::uint8_t>(0xF0 + i));
  const auto rows = block_rows(b);
  REQUIRE(rows.size() == 2);
  CHECK(rows[0] == "F0 F1 F2 F3 F4 F5 F6 F7 F8 F9 FA FB FC FD FE FF");
  CHECK(rows[1] == "00 01");
  CHECK(block_rows(Bytes{}).empty());
  CHECK(parse_row("46 00 03") == std::optional<Bytes>(Bytes{0x46, 0x00, 0x03}));
  CHECK(parse_row("ab") == std::optional<Bytes>(Bytes{0xAB}));
  CHECK(parse_row(rows[0]) == std::optional<Bytes>(Bytes(b.begin(), b.begin() + 16)));
  CHECK_FALSE(parse_row(""));
  CHECK_FALSE(parse_row("4"));
  CHECK_FALSE(parse_row("46  00"));         // two blanks
  CHECK_FALSE(parse_row("46,00"));          // another separator
  CHECK_FALSE(parse_row("46 00 "));         // trailing blank
  CHECK_FALSE(parse_row("4G"));             // not hex
  CHECK_FALSE(parse_row(rows[0] + " 00"));  // 17 bytes
}

TEST_CASE("io_common: decimals without sign, blanks or leading zeros", "[config][io_common]") {
  CHECK(parse_decimal("0") == std::optional<std::uint64_t>(0));
  CHECK(parse_decimal("4294967295") == std::optional<std::uint64_t>(4294967295u));
  CHECK(parse_decimal("9999999999999999999") ==
        std::optional<std::uint64_t>(9999999999999999999ull));
  CHECK_FALSE(parse_decimal("10000000000000000000"));  // 20 digits
  CHECK_FALSE(parse_decimal("007"));
  CHECK_FALSE(parse_decimal("+7"));
  CHECK_FALSE(parse_decimal(" 7"));
  CHECK_FALSE(parse_decimal(""));
  CHECK(parse_signed_decimal("-5") == std::optional<std::int64_t>(-5));
  CHECK(parse_signed_decimal("7") == std::optional<std::int64_t>(7));
  CHECK(parse_signed_decimal("9223372036854775807") ==
        std::optional<std::int64_t>(9223372036854775807LL));
  CHECK_FALSE(parse_signed_decimal("9223372036854775808"));
  CHECK_FALSE(parse_signed_decimal("-0"));
  CHECK_FALSE(parse_signed_decimal("-"));
  CHECK_FALSE(parse_signed_decimal("--1"));
}

TEST_CASE("io_common: DeviceNet motors and command IDs", "[config][io_common]") {
  CHECK(devicenet_motor_text(kDevicenetController) == "controller");
  CHECK(devicenet_motor_text(0) == "A");
  CHECK(devicenet_motor_text(3) == "D");
  CHECK(parse_devicenet_motor("controller") == std::optional<int>(kDevicenetController));
  CHECK(parse_devicenet_motor("B") == std::optional<int>(1));
  CHECK_FALSE(parse_devicenet_motor("E"));
  CHECK_FALSE(parse_devicenet_motor("a"));
  CHECK_FALSE(parse_motor_letter("controller"));
  CHECK(parse_motor_letter("D") == std::optional<int>(3));
  CHECK(command_hex(0x34) == "34");
  CHECK(command_hex(0x0A) == "0A");
  CHECK(parse_command_hex("3a") == std::optional<std::uint8_t>(0x3A));
  CHECK_FALSE(parse_command_hex("3"));
  CHECK_FALSE(parse_command_hex("034"));
  CHECK_FALSE(parse_command_hex("xz"));
}

TEST_CASE("io_common: format and format_version checks say what was expected and where",
          "[config][io_common]") {
  CHECK(check_format_id("lmcfg-drive-config", "f.json:2:13: /format").ok());
  auto id = check_format_id("other", "f.json:2:13: /format");
  REQUIRE_FALSE(id.ok());
  CHECK(id.error().code == make_error_code(Errc::unsupported_version));
  CHECK(id.error().message ==
        "f.json:2:13: /format: expected format \"lmcfg-drive-config\", found \"other\"");
  CHECK(check_format_version(1, "f.json", "f.json:3:21: /format_version").ok());
  CHECK(check_format_version(3, "f.json", "f.json:3:21: /format_version").ok());
  auto newer = check_format_version(4, "f.json", "f.json:3:21: /format_version");
  REQUIRE_FALSE(newer.ok());
  CHECK(newer.error().message ==
        "f.json: file format_version 4 is newer than this lmcfg supports (3); update lmcfg");
  auto older = check_format_version(0, "f.xml", "f.xml: /lmcfg/@format_version");
  REQUIRE_FALSE(older.ok());
  CHECK(older.error().code == make_error_code(Errc::unsupported_version));
  CHECK(older.error().message ==
        "f.xml: /lmcfg/@format_version: expected format_version 1..3, found 0");
}

}  // namespace config_test_io_common

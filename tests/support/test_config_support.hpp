#pragma once
// Shared by tests/config/test_config_*.cpp: the seed 003 example configuration and
// small file helpers.
#if __has_include(<sys/wait.h>)
#include <sys/wait.h>
#endif

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "common/bytes.hpp"
#include "config/model.hpp"
#include "files.hpp"

namespace lmcfg::config::testing {

using lmcfg::test::slurp;
using lmcfg::test::spit;

inline std::filesystem::path fixture_dir() {
  return std::filesystem::path(LMCFG_SOURCE_DIR) / "tests" / "fixtures" / "config";
}

inline Bytes hex(const char* s) { return *from_hex(s); }

// LinRS §11.1: curve 1 "SinRise" as read (70-byte info block, 21 setpoints).
inline Bytes sinrise_info() {
  return hex(
      "46 00 03 00 15 00 04 00 53 69 6E 52 69 73 65 00"
      "00 00 00 00 00 00 00 00 00 00 00 00"
      "00 00 01 00 A0 86 01 00 1A 00 05 00 01 03 A0 86 01 00 00 00 00 00 40 42 0F 00"
      "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00");
}
inline Bytes sinrise_data() {
  // Setpoint 1's Rx line lost a byte in the transcription (LinRS §11.1 erratum);
  // a sine rise from 0 starts at 0.
  return hex(
      "00 00 00 00 0C 18 00 00 98 5F 00 00 E1 D4 00 00 04 75 01 00 0F 3C 02 00"
      "1B 25 03 00 6D 2A 04 00 94 45 05 00 97 6F 06 00 20 A1 07 00 A9 D2 08 00"
      "AC FC 09 00 D3 17 0B 00 25 1D 0C 00 31 06 0D 00 3C CD 0D 00 5F 6D 0E 00"
      "A8 E2 0E 00 34 2A 0F 00 40 42 0F 00");
}
// LinRS §12.1: command table entry 2 (64 bytes).
inline Bytes ct_entry2() {
  return hex(
      "01 A7 FF FF 00 01 40 42 0F 00 20 A1 07 00 40 0D 03 00 40 0D 03 00"
      "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00"
      "55 6E 6E 61 6D 65 64 00 00 00 00 00 00 00 00 00"
      "FF FF FF FF FF FF FF FF FF FF");
}

inline Parameter param(std::uint16_t upid, std::uint32_t value) {
  Parameter p;
  p.upid = upid;
  p.value = value;
  return p;
}

// The configuration of tests/fixtures/config/golden-sinrise.{json,xml}.
inline DriveConfig golden_sinrise() {
  DriveConfig c;
  auto& id = c.identity;
  id.macid = "example";
  id.link = LinkSettings{"/dev/ttyUSB0", "57600", "none", "1", "none"};
  id.tool_version = "0.1.0";
  id.captured_at = "2024-01-01T00:00:00Z";
  id.labels = {{"axis", "X"}, {"machine", "seed 003 example"}};
  c.layer(2).push_back(param(0x13A2, 16));
  c.layer(3) = {param(0x200E, 2), param(0x2012, 8), param(0x206C, 3), param(0x2076, 0x11)};
  c.curves.push_back(Curve{1, sinrise_info(), sinrise_data()});
  c.ct_entries.push_back(CtEntry{2, ct_entry2()});
  return c;
}

// A configuration using every field (display fields, types, labels, scope flags).
inline DriveConfig everything() {
  DriveConfig c = golden_sinrise();
  auto& id = c.identity;
  id.product = "E1100-RS";
  id.firmware = "6.10";
  id.upid_fingerprint = "sha256:0123abcd";
  id.upid_db_version = "2024.1";
  id.upid_db_hash = "sha256:feedbeef";
  id.labels["note"] = "quotes \" < > & ' and ünïcödé";
  id.labels["spaces"] = "  padded  ";
  c.scope.parameters = ParamSet::full;
  c.scope.layers = {true, true, true, false};
  Parameter p = param(0x0005, 0xFFFFFFFF);
  p.type = 6;
  p.name = "Some Signed";
  p.scaled = "-1";
  p.unit = "mm";
  c.layer(1).push_back(p);
  c.layer(2)[0].type = 3;
  c.layer(2)[0].name = "Example & <name>";
  c.layer(2)[0].scaled = "1.6";
  c.layer(2)[0].unit = "A";
  Curve small{7, sinrise_info(), {}};
  small.info[4] = 0;  // zero setpoints
  c.curves.push_back(small);
  Curve tiny{9, hex("08 00 03 00 02 00 04 00"), hex("01 00 00 00 FF FF FF FF")};
  c.curves.push_back(tiny);  // too short to decode: no decoded view
  c.ct_entries.push_back(CtEntry{0, hex("01")});
  c.ct_entries.push_back(CtEntry{255, ct_entry2()});
  canonicalize(c);
  return c;
}

// The configuration of tests/fixtures/config/devicenet.{json,xml}: a DeviceNet
// controller (seed 000) with motors A and B, values by Get command ID.
inline DriveConfig devicenet_capture() {
  DriveConfig c;
  c.scope.layers = {false, false, false, false};
  c.scope.curves = false;
  c.scope.command_table = false;
  auto& id = c.identity;
  id.macid = "5";
  id.link.port = "slcan:/dev/ttyACM0";
  id.link.baud = "125000";
  id.tool_version = "0.1.0";
  id.captured_at = "2024-01-01T00:00:00Z";
  id.labels = {{"machine", "press 2"}};
  DevicenetSection dn;
  dn.can_bitrate = 125000;
  dn.io_modules = {"control-in", "addressed-in", "status-out", "addressed-out"};
  dn.motors = {0, 1};
  // motor, Get command, raw word, name, unit, scaled
  dn.values = {{0, 0x34, 1000, "Get Controller P", "A/mm", "2.3438"},
               {0, 0x40, 0xFE00, "Get Minimal Position", "mm", "-10"},
               {1, 0x34, 1200, "Get Controller P", "A/mm", "2.81256"},
               {1, 0x24, 3, "Get (Rise) Curve Number", "", ""}};
  dn.live = {{kDevicenetController, 0x02, 3, "Get Status Low Word", "", ""},
             {0, 0x18, 512, "Get Actual Position", "mm", "10"}};
  c.devicenet = std::move(dn);
  canonicalize(c);
  return c;
}

// The value of a result the test needs, or the test stops with its message.
template <typename T>
T must(Result<T> r) {
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  return std::move(r).value();
}

inline int run(const std::string& cmd) {
  int rc = std::system((cmd + " >/dev/null 2>&1").c_str());
  if (rc == -1) return -1;
#ifdef WEXITSTATUS
  return WEXITSTATUS(rc);
#else
  return rc;  // Windows: std::system returns the exit code itself
#endif
}

// tests/fixtures/config/bad/*: file, error code, whether the schema validator
// also rejects it (false where only lmcfg's semantic checks can), exact message.
struct BadCase {
  const char* file;
  Errc code;
  bool schema_rejects;
  const char* message;
};
inline constexpr BadCase kBadCases[] = {
#include "../fixtures/config/bad/expected.inc"
};
inline constexpr std::size_t kBadCaseCount = sizeof(kBadCases) / sizeof(kBadCases[0]);

}  // namespace lmcfg::config::testing

// `--port rfc2217://HOST:PORT` through the real ser2net (Debian package, its
// telnet(rfc2217) accepter) in front of `lmcfg sim --pty`: the server's port is
// configured at 9600 Bd and the simulated drive listens at 57600 Bd, so only a
// client that sets the server's rate (RFC 2217 SET-BAUDRATE) reaches it.
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>

#include "files.hpp"
#include "pty_sim.hpp"
#include "ser2net_rig.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_rfc2217_cli {

using namespace lmcfg;

namespace {

// Skips (printed) without ser2net, fails where scripts/test.sh requires it.
bool have_ser2net() {
  const std::string missing = test::ser2net_missing();
  if (missing.empty()) return true;
  if (test::ser2net_required()) FAIL("LMCFG_REQUIRE_SER2NET=1 but " + missing);
  WARN("SKIP: " + missing);
  return false;
}

}  // namespace

TEST_CASE("rfc2217 cli: backup, diff and get through ser2net set the server's rate",
          "[cli][rfc2217][ser2net]") {
  if (!have_ser2net()) return;
  test::PtySim sim;
  test::Ser2netRig rig(sim.tty, 9600);
  REQUIRE(rig.ok());
  const auto dir = test::temp_dir("rfc2217-cli");
  const std::string port = "--port rfc2217://127.0.0.1:" + std::to_string(rig.port);

  auto b = test::run_tool_in(dir, "backup " + port + " -o axis.json --quiet");
  INFO(b.err);
  REQUIRE(b.exit_code == 0);
  // The same drive over its pseudo-terminal directly: the same configuration.
  rig.process.reset();  // ser2net releases the pty
  auto direct = test::run_tool_in(dir, "backup --port " + sim.tty + " -o direct.json --quiet");
  REQUIRE(direct.exit_code == 0);
  auto d = test::run_tool_in(dir, "diff axis.json direct.json --ignore-metadata");
  CHECK(d.exit_code == 0);
}

TEST_CASE("rfc2217 cli: a rate no drive listens at is a link failure, scan finds the drive's rate",
          "[cli][rfc2217][ser2net]") {
  if (!have_ser2net()) return;
  test::PtySim sim;
  test::Ser2netRig rig(sim.tty, 9600);
  REQUIRE(rig.ok());
  const auto dir = test::temp_dir("rfc2217-scan");
  const std::string url = "rfc2217://127.0.0.1:" + std::to_string(rig.port);

  auto wrong = test::run_tool_in(dir, "get 13A2 --baud 19200 --retries 0 --port " + url);
  CHECK(wrong.exit_code == 4);
  CHECK(wrong.err.find("no answer from MACID 11h at 19200 Bd") != std::string::npos);

  // scan tries the rates through the server: the drive at 57600 is found.
  auto s = test::run_tool_in(dir, "scan --from 0x11 --to 0x11 --json --port " + url);
  INFO(s.err);
  CHECK(s.exit_code == 0);
  CHECK(s.out.find("\"options\": \"--baud 57600 --id 0x11 --checksum none\"") != std::string::npos);
}

}  // namespace tools_test_rfc2217_cli

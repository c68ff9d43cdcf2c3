// `lmcfg link` end to end against `lmcfg sim` on a pseudo-terminal: the
// server follows the drive to its new rate and checksum after the reset, so
// the new link options are tested on the wire the tool really uses. The
// simulated firmware keeps its checksum at 20A0h, a stand-in (LinRS §15
// names the setting without a UPID) that the tests pass with --map.
#include <catch2/catch.hpp>
#include <filesystem>
#include <sstream>

#include "e2e_support.hpp"
#include "files.hpp"
#include "ops/recovery.hpp"
#include "sim/state_file.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_link_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

const std::string kMap = " --map checksum@20A0:none=0,add=1,crc=2";

void write_spare(const fs::path& file, bool silent_after_reset = false) {
  auto st = sim::load_state(test::sim_fixture("used-spare.json"));
  REQUIRE(st.ok());
  sim::Parameter p;
  p.upid = 0x20A0;
  p.name = "Checksum (test stand-in)";
  p.max = 2;
  st->put(p);
  st->options.checksum_param =
      sim::Options::CommParam{0x20A0, {{0, "none"}, {1, "add"}, {2, "crc-ffff"}}};
  st->options.silent_after_reset = silent_after_reset;
  REQUIRE(sim::save_state(*st, file.string()).ok());
}

struct PtySpare {
  test::ScratchDir dir{"link-cli"};
  std::unique_ptr<test::Child> sim;
  std::string tty;
  explicit PtySpare(bool silent = false) {
    write_spare(dir.path / "spare.sim.json", silent);
    sim = std::make_unique<test::Child>(
        std::vector<std::string>{LMCFG_TOOL_PATH, "sim", "--state",
                                 (dir.path / "spare.sim.json").string(), "--pty", "--fast"});
    tty = sim->read_line();
    REQUIRE(tty.rfind("/dev/pts/", 0) == 0);
  }
  test::ToolRun run(const std::string& args) { return test::run_tool_in(dir.path, args); }
};

std::size_t tx_lines(const fs::path& trace) {
  std::istringstream in(test::slurp(trace));
  std::size_t n = 0;
  for (std::string line; std::getline(in, line);) n += line.find(" TX") != std::string::npos;
  return n;
}

}  // namespace

TEST_CASE("link cli: shows the LinRS settings as the drive holds them", "[link][pty]") {
  PtySpare s;
  auto r = s.run("link --port " + s.tty + kMap);
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.out ==
        "drive 11h on " + s.tty +
            " (ROM values), talking at: --baud 57600 --id 0x11 --checksum none\n"
            "  baud rate source: 200Eh = 1 (hex switch S1)\n"
            "  baud rate: 2012h = 32 (raw value 32 not in the map)\n"
            "  MACID source: 206Ch = 1 (hex switches (S2, or S1 and S2))\n"
            "  MACID: 2076h = 17 (11h)\n"
            "  checksum: 20A0h = 0 (none)\n"
            "  parity: unknown (UPID unknown: seed 003 §15 names the setting but not its UPID; "
            "give it with --map parity@UPID:VALUE=RAW,...)\n"
            "  stop bits: unknown (UPID unknown: seed 003 §15 names the setting but not its UPID; "
            "give it with --map stop-bits@UPID:VALUE=RAW,...)\n");
}

TEST_CASE(
    "link cli: --set-checksum crc, then a backup with the printed link options sends fewer "
    "telegrams",
    "[link][pty]") {
  PtySpare s;
  auto before = s.run("backup -o before.json --port " + s.tty + " --trace before.trace --quiet");
  REQUIRE(before.exit_code == 0);
  auto r = s.run("link --port " + s.tty + kMap + " --set-checksum crc --yes");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("  20A0h checksum: 0 (none) -> 2 (crc-ffff)\n") != std::string::npos);
  CHECK(r.out.find("the drive answers at 57600 Bd, MACID 11h, checksum crc-ffff; read back: every "
                   "value as written\n"
                   "link options: --port " +
                   s.tty + " --baud 57600 --id 0x11 --checksum crc-ffff\n") != std::string::npos);
  CHECK(r.out.find("fleet: for an inventory, run with --inventory FILE --drive NAME") !=
        std::string::npos);
  // The old link options reach nothing now (exit 4).
  CHECK(s.run("info --port " + s.tty + " --timeout-ms 50 --retries 0").exit_code == 4);
  auto after = s.run("backup -o after.json --port " + s.tty +
                     " --baud 57600 --id 0x11 --checksum crc-ffff --trace after.trace --quiet");
  INFO(after.err);
  REQUIRE(after.exit_code == 0);
  const auto n_before = tx_lines(s.dir.path / "before.trace");
  const auto n_after = tx_lines(s.dir.path / "after.trace");
  INFO("telegrams sent: without checksum " << n_before << ", with crc " << n_after);
  CHECK(n_after < n_before);
  // The same configuration but the checksum parameter itself.
  auto diff = s.run("diff before.json after.json --ignore-metadata");
  CHECK(diff.exit_code == 1);
  CHECK(diff.out.find("layer Intf:\n  20A0h (name unknown): default 0 -> 2\n") !=
        std::string::npos);
  CHECK(diff.out.find("\n1 difference(s)\n") != std::string::npos);
}

TEST_CASE("link cli: --set-baud 38400 (2012h = 8, seed 003 §10.2) and the inventory keys",
          "[link][pty]") {
  PtySpare s;
  test::spit(s.dir.path / "plant.toml", "[[line]]\nname = \"press\"\nport = \"" + s.tty +
                                            "\"\n[[line.drive]]\nname = \"axis1\"\nid = 0x11\n"
                                            "[[line.drive]]\nname = \"axis2\"\nid = 0x12\n");
  auto r = s.run("link --port " + s.tty +
                 " --set-baud 38400 --yes --inventory plant.toml --drive axis1");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out.find("  2012h baud rate: 32 -> 8 (38400)\n"
                   "  200Eh baud rate source: 1 (hex switch S1) -> 2 (By Parameter)\n") !=
        std::string::npos);
  CHECK(r.out.find("link options: --port " + s.tty + " --baud 38400 --id 0x11 --checksum none\n" +
                   "inventory: plant.toml:1:1: [[line]] \"press\": baud = 38400\n") !=
        std::string::npos);
  CHECK(r.err.find("lmcfg link: warning: line \"press\" (plant.toml:1:1) carries 2 drives on one "
                   "port that share its rate, parity, stop bits and checksum: move the others "
                   "(axis2) to the same settings with lmcfg link before changing the line's keys, "
                   "or the fleet commands reach only part of the line\n") != std::string::npos);
  auto shown = s.run("link --port " + s.tty + " --baud 38400");
  INFO(shown.err);
  CHECK(shown.exit_code == 0);
  CHECK(shown.out.find("  baud rate: 2012h = 8 (38400)\n") != std::string::npos);
  // Back to the factory rate: 2012h's default on the drive is 57600 Bit/s (§15).
  auto back = s.run("link --port " + s.tty + " --baud 38400 --set-baud 57600 --yes");
  INFO(back.err);
  REQUIRE(back.exit_code == 0);
  CHECK(back.out.find("  2012h baud rate: 8 (38400) -> 16 (57600)\n"
                      "the drive answers at 57600 Bd, MACID 11h, checksum none") !=
        std::string::npos);
}

TEST_CASE("link cli: --dry-run writes nothing", "[link][pty]") {
  PtySpare s;
  auto r = s.run("link --port " + s.tty + kMap + " --set-checksum add --set-baud 38400 --dry-run");
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(r.out == "drive 11h on " + s.tty +
                     ": write to ROM (MC stopped, seed 003 §10), then reset (§13.1):\n"
                     "  2012h baud rate: 32 -> 8 (38400)\n"
                     "  200Eh baud rate source: 1 (hex switch S1) -> 2 (By Parameter)\n"
                     "  20A0h checksum: 0 (none) -> 1 (add)\n"
                     "link options after the reset: --baud 38400 --id 0x11 --checksum add\n"
                     "fleet: for an inventory, run with --inventory FILE --drive NAME to see the "
                     "keys to change\n"
                     "dry run: nothing written\n");
  // Read back at the old settings: the ROM values are unchanged.
  auto shown = s.run("link --port " + s.tty + kMap + " --json");
  REQUIRE(shown.exit_code == 0);
  CHECK(shown.out.find("\"setting\": \"baud\",\n      \"upid\": \"2012\",\n      \"rom\": 32") !=
        std::string::npos);
  CHECK(shown.out.find("\"setting\": \"checksum\",\n      \"upid\": \"20A0\",\n      \"rom\": 0") !=
        std::string::npos);
  CHECK_FALSE(fs::exists(s.dir.path / "lmcfg"));  // no recovery record either
}

TEST_CASE("link cli: refusals: a value without a raw value, no terminal, a DeviceNet port",
          "[link][pty]") {
  PtySpare s;
  auto fast = s.run("link --port " + s.tty + " --set-baud 115200 --yes");
  CHECK(fast.exit_code == 2);
  CHECK(fast.err ==
        "lmcfg link: --set-baud 115200: no raw value of 2012h baud rate is known for 115200 "
        "(known: 38400 = 8; seed 003 states only 8 = 38400 Baud, §10.2); give it with --map "
        "baud:115200=RAW; nothing written\n");
  auto ask = s.run("link --port " + s.tty + kMap + " --set-checksum crc");
  CHECK(ask.exit_code == 2);
  CHECK(ask.err ==
        "lmcfg link: refusing to change a drive's link settings without --yes when stdin is not "
        "a terminal; nothing written\n");
  auto bad = s.run("link --port " + s.tty + " --set-stop-bits 3");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err == "lmcfg link: --set-stop-bits '3': not 1 or 2; nothing written\n");
  auto dn = s.run("link --port slcan:/dev/null --set-baud 38400");
  CHECK(dn.exit_code == 2);
  CHECK(dn.err ==
        "lmcfg link: --port slcan:/dev/null is a DeviceNet (CAN) link: lmcfg link changes the "
        "LinRS settings of seed 003 §15; a DeviceNet controller's MACID and bit rate are set with "
        "its switches or the vendor's PC software (seed 000 §1.1); nothing written\n");
  auto shown = s.run("link --port " + s.tty + kMap + " --json");
  REQUIRE(shown.exit_code == 0);
  CHECK(shown.out.find("\"setting\": \"checksum\",\n      \"upid\": \"20A0\",\n      \"rom\": 0") !=
        std::string::npos);
}

TEST_CASE("link cli: a drive lost after the reset: exit 4, the record and the scan to run",
          "[link][pty]") {
  PtySpare s(true);
  // The drive is looked for again up to --recover-timeout-s (180 s by default,
  // docs/field.md) before the scan: 1 s here, so the test does not wait it out.
  auto r = s.run("link --port " + s.tty + kMap +
                 " --set-checksum crc --yes --timeout-ms 50 --recover-timeout-s 1");
  INFO(r.err);
  CHECK(r.exit_code == 4);
  const fs::path record = s.dir.path / "lmcfg" / ("link-" + ops::drive_key(s.tty, 0x11) + ".json");
  CHECK(r.err.find("The drive holds 20A0h = 2 in ROM and restarted with them (expected: --baud "
                   "57600 --id 0x11 --checksum crc-ffff); the recovery record " +
                   record.string() +
                   " holds the previous values (--baud 57600 --id 0x11 --checksum none). Find it "
                   "with: lmcfg scan --port " +
                   s.tty + "\n") != std::string::npos);
  CHECK(fs::exists(record));
}

}  // namespace tools_test_link_cli

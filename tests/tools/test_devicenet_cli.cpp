// DeviceNet controllers (seed 000) end to end: `lmcfg backup`, `diff` and
// `restore` through a real pseudo-terminal to `lmcfg sim --devicenet` (a
// simulated slcan adapter in front of a simulated controller), with poll
// responses lost on the way; and the bad inputs (wrong bit rate, MAC ID, a second master, bad
// values), each with its message and exit code.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "can/link.hpp"
#include "config/config_io.hpp"
#include "devicenet/master.hpp"
#include "devicenet_sim.hpp"
#include "files.hpp"
#include "link/port.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_devicenet_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

using DnSim = test::DevicenetSim;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// Backup, diff (identical), two values changed by another master, diff
// (exactly those two), restore (exactly two Set commands, verified), diff
// again identical, a second restore with nothing to do.
void backup_change_restore(const DnSim& sim, const std::string& dir_name,
                           const std::string& restore_options) {
  REQUIRE(sim.port.rfind("slcan:", 0) == 0);
  const auto dir = test::temp_dir(dir_name);

  auto backup = test::run_tool_in(dir, "backup " + sim.link() + " -o ctl.json");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  CHECK(backup.err.find("backup: DeviceNet MAC ID 5: 2 motor(s), ") != std::string::npos);
  CHECK(backup.err.find("runtime values") != std::string::npos);
  auto file = config::read_config_file((dir / "ctl.json").string());
  REQUIRE(file.ok());
  REQUIRE(file->devicenet);
  CHECK(file->devicenet->motors == std::vector<int>{0, 1});
  CHECK(file->devicenet->values.size() > 40);

  auto same = test::run_tool_in(dir, "diff ctl.json drive " + sim.link());
  INFO(same.out << same.err);
  CHECK(same.exit_code == 0);

  test::change_two_values(sim);
  auto changed = test::run_tool_in(dir, "diff ctl.json drive " + sim.link() + " --json");
  INFO(changed.out << changed.err);
  CHECK(changed.exit_code == 1);
  const auto j = nlohmann::json::parse(changed.out);
  std::vector<std::string> names;
  for (const auto& item : j["differences"])
    if (item["kind"] == "devicenet") names.push_back(item["name"]);
  CHECK(names == std::vector<std::string>{"motor A: Controller P (34h)",
                                          "motor B: Filter Maximal Speed (50h)"});
  CHECK(j["differences"].size() == 2);
  CHECK(changed.out.find("A/mm") != std::string::npos);
  CHECK(changed.out.find("mm/s") != std::string::npos);

  auto restore =
      test::run_tool_in(dir, "restore ctl.json --yes " + sim.link() + " " + restore_options);
  INFO(restore.out << restore.err);
  REQUIRE(restore.exit_code == 0);
  CHECK(count(restore.out, "  set ") == 2);
  CHECK(restore.out.find("  set 35h motor A: Controller P (34h): ") != std::string::npos);
  CHECK(restore.out.find("  set 51h motor B: Filter Maximal Speed (50h): ") != std::string::npos);
  CHECK(restore.err.find("restore: 2 Set command(s) sent, verified") != std::string::npos);
  // The journal records the two Set commands (docs/audit.md).
  const std::string journal = test::slurp(dir / "lmcfg" / "journal.jsonl");
  REQUIRE(std::count(journal.begin(), journal.end(), '\n') == 1);
  const auto rec = nlohmann::json::parse(journal);
  CHECK(rec["command"] == "restore");
  CHECK(rec["outcome"] == "restored and verified");
  REQUIRE(rec["steps"].size() == 2);
  CHECK(rec["steps"][0]["action"] == "devicenet_set");
  CHECK(rec["steps"][0]["motor"] == "A");
  CHECK(rec["steps"][0]["command"] == "35h");
  CHECK(rec["steps"][1]["command"] == "51h");

  auto again = test::run_tool_in(dir, "diff ctl.json drive " + sim.link());
  INFO(again.out << again.err);
  CHECK(again.exit_code == 0);
  auto nothing = test::run_tool_in(dir, "restore ctl.json --yes " + sim.link());
  CHECK(nothing.exit_code == 0);
  CHECK(nothing.out.find("nothing to do: the controller already matches ctl.json") !=
        std::string::npos);
  auto skip = test::run_tool_in(dir, "restore ctl.json --yes --skip-incompatible " + sim.link());
  CHECK(skip.exit_code == 2);
  CHECK(skip.err ==
        "lmcfg restore: --skip-incompatible is a LinRS option; a DeviceNet restore plans against "
        "Table 5-1's ranges and refuses any value outside\n");
  fs::remove_all(dir);
}

}  // namespace

TEST_CASE(
    "DeviceNet §5.2 backup, diff, change two values, diff, restore exactly two, over "
    "slcan on a pty with lost poll responses",
    "[devicenet][cli][pty]") {
  DnSim sim({"--lose-polls", "0.05", "--seed", "7"});
  backup_change_restore(sim, "dn-e2e", "--retries 4");
}

TEST_CASE("DeviceNet §5.2 a wrong bit rate, a wrong MAC ID, a second master",
          "[devicenet][cli][pty]") {
  const auto dir = test::temp_dir("dn-link");
  {
    DnSim sim;
    auto r = test::run_tool_in(dir, "backup " + sim.link() + " --can-bitrate 250000 -o x.json");
    CHECK(r.exit_code == 4);
    CHECK(r.err ==
          "lmcfg backup: no answer from DeviceNet MAC ID 5 to Allocate_Master/Slave_Connection_Set "
          "within 100 ms on slcan serial " +
              sim.pty +
              " 115200 8N1 250 kbit/s (adapter version 1013): the adapter reports CAN bus errors "
              "(status flags A0h): no "
              "node acknowledged the frames, so the bit rate is probably wrong: check "
              "--can-bitrate (125000, 250000 or 500000, the controller's DeviceNet\\Baudrate) and "
              "that the adapter is connected to the DeviceNet bus\n");
    CHECK(!fs::exists(dir / "x.json"));
  }
  {
    DnSim sim;
    auto r = test::run_tool_in(
        dir, "backup --port slcan:" + sim.pty +
                 " --devicenet-macid 6 --devicenet-listen-ms 20 --timeout-ms 100 -o x.json");
    CHECK(r.exit_code == 4);
    CHECK(r.err.find("no answer from DeviceNet MAC ID 6") != std::string::npos);
    CHECK(r.err.find("the bus carried the frames without errors, so the bit rate fits; check "
                     "--devicenet-macid") != std::string::npos);
  }
  {
    DnSim sim({"--held-by", "2"});
    auto r = test::run_tool_in(dir, "backup " + sim.link() + " -o x.json");
    CHECK(r.exit_code == 5);
    CHECK(r.err ==
          "lmcfg backup: DeviceNet MAC ID 5 refused the connection: error response to "
          "Allocate_Master/Slave_Connection_Set 4Bh: general error 0Ch object state conflict, "
          "additional 01h; another master (a PLC's scanner) probably holds it: the controller "
          "serves one master at a time (seed 000 §2.6)\n");
  }
  {
    auto r = test::run_tool_in(dir, "backup --port slcan:/dev/null --devicenet-macid 64 -o x.json");
    CHECK(r.exit_code == 2);
    CHECK(r.err == "lmcfg backup: --devicenet-macid '64' is not a DeviceNet MAC ID 0..63\n");
    r = test::run_tool_in(dir, "backup --port slcan:/dev/null -o x.json");
    CHECK(r.exit_code == 2);
    CHECK(r.err ==
          "lmcfg backup: --port slcan:/dev/null is a CAN link: give the controller's "
          "--devicenet-macid\n");
    r = test::run_tool_in(dir,
                          "backup --port slcan:/dev/null --devicenet-macid 5 --can-bitrate "
                          "100000 -o x.json");
    CHECK(r.exit_code == 2);
    CHECK(r.err ==
          "lmcfg backup: --can-bitrate 100000 is not a DeviceNet bit rate (125000, "
          "250000, 500000)\n");
  }
  CHECK(!fs::exists(dir / "x.json"));
  fs::remove_all(dir);
}

TEST_CASE(
    "DeviceNet §5.2 a controller without the Addressed modules, an out-of-range value in "
    "a file",
    "[devicenet][cli][pty]") {
  const auto dir = test::temp_dir("dn-input");
  {
    DnSim sim({"--io-modules", "control-in,status-out"});
    auto r = test::run_tool_in(dir, "backup " + sim.link() + " -o x.json");
    CHECK(r.exit_code == 2);
    CHECK(r.err ==
          "lmcfg backup: DeviceNet MAC ID 5's polled connection takes 2 byte(s) and gives 4, but "
          "the IO layout 6/8 was expected: it cannot hold the Addressed In and Addressed Out "
          "modules the configuration commands need (seed 000 §5.1, §5.2). Configure the "
          "controller's IO setup with LinTalk to include Addressed In and Addressed Out (the "
          "default: Control In + Addressed In, Status Out + Addressed Out), then run again\n");
  }
  DnSim sim;
  test::backup_and_out_of_range(sim, dir);
  auto r = test::run_tool_in(dir, "restore bad.json --yes " + sim.link());
  CHECK(r.exit_code == 3);
  CHECK(r.err.find("restore plan for bad.json: REFUSED, nothing written:\n  problem: motor B: In "
                   "Position Low Limit (48h): 11.71875 mm (raw 600) is outside Table 5-1's range "
                   "2 to 511 (unit 0.01953 mm)\n") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE(
    "DeviceNet §5.2 a firmware whose refusals stop RUN is told so, --devicenet-motors and "
    "--no-module-values avoid the probes",
    "[devicenet][cli][pty]") {
  const auto dir = test::temp_dir("dn-run");
  DnSim sim({"--error-leaves-run"});
  auto probed = test::run_tool_in(dir, "backup " + sim.link() + " -o probed.json");
  CHECK(probed.exit_code == 0);
  CHECK(probed.err.find("devicenet: the controller left RUN state during the backup (status "
                        "0005h), after refusing a read; seed 000 §5.2: RUN Request must be "
                        "released and set again (the PLC's Control Word). --devicenet-motors and "
                        "--no-module-values avoid the probes\n") != std::string::npos);
  DnSim fresh({"--error-leaves-run"});
  auto quiet = test::run_tool_in(
      dir, "backup " + fresh.link() + " --devicenet-motors A,B --no-module-values -o x.json");
  CHECK(quiet.exit_code == 0);
  CHECK(quiet.err.find("left RUN") == std::string::npos);
  CHECK(quiet.err.find("not read") == std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE(
    "DeviceNet §5.2 a controller reset in the middle of a restore is reported as partial, "
    "the rerun converges",
    "[devicenet][cli][pty]") {
  const auto dir = test::temp_dir("dn-reset");
  DnSim sim({"--reset-after-sets", "3"});  // the two sets below, then the restore's first
  REQUIRE(test::run_tool_in(dir, "backup " + sim.link() + " -q -o ctl.json").exit_code == 0);
  test::change_two_values(sim);
  auto partial = test::run_tool_in(dir, "restore ctl.json --yes " + sim.link());
  INFO(partial.out << partial.err);
  CHECK(partial.exit_code == 4);
  CHECK(partial.err.find("lmcfg restore: the controller is partially restored: ") !=
        std::string::npos);
  CHECK(partial.err.find("0 of 2 Set command(s) done before it, the rest not sent: run the "
                         "restore again)") != std::string::npos);
  auto rerun = test::run_tool_in(dir, "restore ctl.json --yes " + sim.link());
  INFO(rerun.out << rerun.err);
  CHECK(rerun.exit_code == 0);
  CHECK(count(rerun.out, "  set ") == 1);  // the first Set had executed before the reset
  CHECK(test::run_tool_in(dir, "diff ctl.json drive " + sim.link()).exit_code == 0);
  fs::remove_all(dir);
}

TEST_CASE("DeviceNet §5.2 Ctrl-C during a backup releases the connection (exit 130)",
          "[devicenet][cli][pty]") {
  const auto dir = test::temp_dir("dn-sigint");
  DnSim sim({"--lose-polls", "0.3"});  // a slow line: the signal lands mid-backup
  test::Child backup({LMCFG_TOOL_PATH, "backup", "--port", "slcan:" + sim.pty, "--devicenet-macid",
                      "5", "--devicenet-listen-ms", "20", "--timeout-ms", "100", "--retries", "9",
                      "-q", "-o", (dir / "x.json").string()});
  ::usleep(600 * 1000);
  CHECK(backup.stop() == 130);
  CHECK(!fs::exists(dir / "x.json"));
  test::change_two_values(sim);  // another master gets the connection: it was released
  fs::remove_all(dir);
}

TEST_CASE(
    "devicenet: backup, diff, change, restore and verify against each reading of seed 000 §5.2's "
    "toggle rule",
    "[devicenet][cli][pty][toggle]") {
  for (const std::string rule : {"seed", "get-set-ignore", "module"}) {
    INFO("--devicenet-toggle " << rule);
    DnSim sim({"--devicenet-toggle", rule});
    backup_change_restore(sim, "dn-toggle", "");
  }
}

TEST_CASE("devicenet: lmcfg sim refuses an unknown --devicenet-toggle",
          "[devicenet][cli][toggle]") {
  const auto dir = test::temp_dir("dn-toggle-bad");
  auto r = test::run_tool_in(dir, "sim --devicenet --devicenet-toggle always");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg sim: --devicenet-toggle 'always' is not one of seed, get-set-ignore, "
        "module\n");
  CHECK(r.out.empty());
  fs::remove_all(dir);
}

TEST_CASE(
    "devicenet: lmcfg sim --devicenet --tcp serves the adapter protocol on loopback TCP, backup, "
    "diff, change, restore and verify over slcan:tcp://",
    "[devicenet][cli][tcp]") {
  DnSim sim({}, DnSim::Where::tcp);
  REQUIRE(sim.announced.find_first_not_of("0123456789") == std::string::npos);
  CHECK(sim.options == "link options: --port slcan:tcp://127.0.0.1:" + sim.announced +
                           " --can-bitrate 125000 --devicenet-macid 5");
  CHECK(sim.pty.empty());
  // Each tool run is a new TCP client; the controller keeps its values between them.
  backup_change_restore(sim, "dn-tcp", "");
}

TEST_CASE("devicenet: lmcfg sim --devicenet refuses a --tcp that is not HOST:PORT and --state",
          "[devicenet][cli][tcp]") {
  const auto dir = test::temp_dir("dn-tcp-bad");
  auto bad = test::run_tool_in(dir, "sim --devicenet --tcp 127.0.0.1:x");
  CHECK(bad.exit_code == 2);
  CHECK(bad.err == "lmcfg sim: --tcp expects HOST:PORT, got '127.0.0.1:x'\n");
  CHECK(bad.out.empty());
  auto state = test::run_tool_in(dir, "sim --devicenet --state axis.json");
  CHECK(state.exit_code == 2);
  CHECK(state.err == "lmcfg sim: --devicenet simulates a controller of its own, without --state\n");
  fs::remove_all(dir);
}

namespace {

// Backup (the motors found by probing), another master changes motor A,
// diff (one difference), restore (one Set command, verified), diff identical.
void backup_restore_motors(const DnSim& sim, int motors, const std::string& dir_name) {
  const auto dir = test::temp_dir(dir_name);
  auto backup = test::run_tool_in(dir, "backup " + sim.link() + " -o ctl.json");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  CHECK(backup.err.find("backup: DeviceNet MAC ID 5: " + std::to_string(motors) + " motor(s), ") !=
        std::string::npos);
  auto file = config::read_config_file((dir / "ctl.json").string());
  REQUIRE(file.ok());
  REQUIRE(file->devicenet);
  std::vector<int> expected;
  for (int m = 0; m < motors; ++m) expected.push_back(m);
  CHECK(file->devicenet->motors == expected);
  test::change_motor_a(sim);
  auto changed = test::run_tool_in(dir, "diff ctl.json drive " + sim.link());
  INFO(changed.out << changed.err);
  CHECK(changed.exit_code == 1);
  CHECK(changed.out.find("motor A: Controller P (34h): ") != std::string::npos);
  auto restore = test::run_tool_in(dir, "restore ctl.json --yes " + sim.link());
  INFO(restore.out << restore.err);
  REQUIRE(restore.exit_code == 0);
  CHECK(count(restore.out, "  set ") == 1);
  CHECK(restore.err.find("restore: 1 Set command(s) sent, verified") != std::string::npos);
  auto again = test::run_tool_in(dir, "diff ctl.json drive " + sim.link());
  INFO(again.out << again.err);
  CHECK(again.exit_code == 0);
  fs::remove_all(dir);
}

}  // namespace

TEST_CASE(
    "devicenet: seed 000 §5.2 backup, diff and restore of controllers with 1 to 4 motors under "
    "each reading of a command for a motor the controller does not have",
    "[devicenet][cli][pty][absent]") {
  const char* motor_lists[] = {"A", "A,B", "A,B,C", "A,B,C,D"};
  for (int n = 1; n <= 4; ++n) {
    for (const char* absent :
         {"coded-error", "coded-error-8110", "no-toggle", "error-no-echo", "echo-only", "ignore"}) {
      if (n == 4 && std::string(absent) != "coded-error") continue;  // no motor is absent
      INFO(motor_lists[n - 1] << ", --devicenet-absent-motor " << absent);
      DnSim sim({"--devicenet-absent-motor", absent}, DnSim::Where::pty, 5, motor_lists[n - 1]);
      backup_restore_motors(sim, n, "dn-absent");
    }
  }
}

TEST_CASE(
    "devicenet: an slcan adapter that answers no command: backup, diff and "
    "restore",
    "[devicenet][cli][pty][slcan]") {
  {
    DnSim sim({"--slcan-silent"});
    backup_change_restore(sim, "dn-silent", "");
  }
  DnSim one(
      {"--slcan-silent", "--devicenet-absent-motor", "ignore", "--devicenet-toggle", "module"},
      DnSim::Where::pty, 5, "A");
  backup_restore_motors(one, 1, "dn-silent-one");
}

TEST_CASE("devicenet: lmcfg sim refuses an unknown --devicenet-absent-motor",
          "[devicenet][cli][absent]") {
  const auto dir = test::temp_dir("dn-absent-bad");
  auto r = test::run_tool_in(dir, "sim --devicenet --devicenet-absent-motor crash");
  CHECK(r.exit_code == 2);
  CHECK(r.err ==
        "lmcfg sim: --devicenet-absent-motor 'crash' is not one of coded-error, "
        "coded-error-8110, no-toggle, error-no-echo, echo-only, ignore\n");
  CHECK(r.out.empty());
  fs::remove_all(dir);
}

}  // namespace tools_test_devicenet_cli

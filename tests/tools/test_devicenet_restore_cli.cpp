// `lmcfg restore` of a DeviceNet controller (seed 000) through the restore
// flow LinRS restores take: `--json --dry-run` and an executed `--json`
// restore report the Set commands in the shape of the LinRS restore's report
// (docs/json-reports.md, schemas/report-restore.schema.json), against
// `lmcfg sim --devicenet` on a pseudo-terminal under each reading of the
// toggle rule; a refused plan and a partial restore as JSON; the text of a
// dry run.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "config/config_io.hpp"
#include "devicenet_sim.hpp"
#include "files.hpp"
#include "json_schema.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_devicenet_restore_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

using DnSim = test::DevicenetSim;
using Json = nlohmann::ordered_json;

// The restore plan's note on every DeviceNet restore (docs/devicenet.md "Runtime values").
const std::string kRuntime =
    "DeviceNet controller values are runtime values: the controller's persistent configuration "
    "is made with the vendor's PC software (seed 000 §1.1), so values written here act until the "
    "next power cycle unless the machine's PLC sets them again";

std::uint16_t value_in(const config::DriveConfig& c, int motor, int command) {
  for (const auto& v : c.devicenet->values)
    if (v.motor == motor && v.command == command) return v.raw;
  FAIL("no value of motor " << motor << " command " << command);
  return 0;
}

std::vector<std::string> keys(const Json& j) {
  std::vector<std::string> k;
  for (const auto& [key, v] : j.items()) k.push_back(key);
  return k;
}

// The two Set commands after test::change_two_values (motor A's Controller P
// at 2000, motor B's Filter Max Speed at 5243) back to the file's values.
// Displays: DeviceNet §5.2 "Command: Set Controller P (35h)", "Detail unit
// 2.3438 mA/mm" (Table 5-1 rounds it to 0.00234 A/mm), and Table 5-1 "0x51
// Set Filter Max Speed 6 to 24576 0.190735 mm/s": 2000 x 2.3438 mA/mm =
// 4.6876 A/mm, 5243 x 0.190735 mm/s = 1000.02 mm/s.
void check_steps(const Json& steps, std::uint16_t p, std::uint16_t speed) {
  REQUIRE(steps.size() == 2);
  const auto& a = steps[0];
  CHECK(keys(a) == std::vector<std::string>{"step", "action", "motor", "command", "name", "old",
                                            "new", "text"});
  CHECK(a["step"] == 1);
  CHECK(a["action"] == "devicenet_set");
  CHECK(a["motor"] == "A");
  CHECK(a["command"] == "35h");
  CHECK(a["name"] == "motor A: Controller P (34h)");
  CHECK(a["old"]["raw"] == 2000);
  CHECK(a["old"]["display"] == "4.6876 A/mm (raw 2000)");
  CHECK(a["new"]["raw"] == p);
  CHECK(a["text"] == "motor A: Controller P (34h): 4.6876 A/mm (raw 2000) -> " +
                         a["new"]["display"].get<std::string>());
  const auto& b = steps[1];
  CHECK(b["step"] == 2);
  CHECK(b["action"] == "devicenet_set");
  CHECK(b["motor"] == "B");
  CHECK(b["command"] == "51h");
  CHECK(b["name"] == "motor B: Filter Maximal Speed (50h)");
  CHECK(b["old"]["raw"] == 5243);
  CHECK(b["old"]["display"].get<std::string>().rfind("1000.02", 0) == 0);
  CHECK(b["old"]["display"].get<std::string>().find(" mm/s (raw 5243)") != std::string::npos);
  CHECK(b["new"]["raw"] == speed);
}

void check_shape(const Json& j, const std::string& outcome) {
  CHECK(keys(j) == std::vector<std::string>{"file", "outcome", "problems", "nothing_to_do", "steps",
                                            "losses", "skipped", "skipped_incompatible", "notes",
                                            "devicenet", "mismatches"});
  CHECK(j["file"] == "ctl.json");
  CHECK(j["outcome"] == outcome);
  CHECK(j["problems"].empty());
  CHECK(j["losses"].empty());
  CHECK(j["skipped"].empty());
  CHECK(j["skipped_incompatible"].empty());
  REQUIRE(!j["notes"].empty());
  CHECK(j["notes"].back() == kRuntime);
  CHECK(j["mismatches"].empty());
}

void json_dry_run_then_restore(const std::string& rule) {
  INFO("--devicenet-toggle " << rule);
  DnSim sim({"--devicenet-toggle", rule});
  test::ScratchDir d("dn-restore-json");
  const auto& dir = d.path;
  REQUIRE(test::run_tool_in(dir, "backup " + sim.link() + " -q -o ctl.json").exit_code == 0);
  auto file = config::read_config_file((dir / "ctl.json").string());
  REQUIRE(file.ok());
  const auto p = value_in(*file, 0, 0x34), speed = value_in(*file, 1, 0x50);
  REQUIRE(p != 2000);
  REQUIRE(speed != 5243);
  const std::size_t values = file->devicenet->values.size();
  test::change_two_values(sim);

  auto dry = test::run_tool_in(dir, "restore ctl.json --json --dry-run " + sim.link());
  INFO(dry.out << dry.err);
  REQUIRE(dry.exit_code == 0);
  const auto j = Json::parse(dry.out);
  check_shape(j, "dry run");
  CHECK(j["nothing_to_do"] == false);
  CHECK(j["devicenet"] == Json{{"unchanged", values - 2}});
  check_steps(j["steps"], p, speed);
  CHECK(dry.err.find("restore plan for") == std::string::npos);  // the plan is the JSON
  CHECK(test::schema_valid(dir, "report-restore.schema.json", dry.out));
  CHECK(!fs::exists(dir / "lmcfg" / "journal.jsonl"));  // nothing written
  CHECK(test::run_tool_in(dir, "diff ctl.json drive " + sim.link()).exit_code == 1);

  auto real = test::run_tool_in(dir, "restore ctl.json --json --yes " + sim.link());
  INFO(real.out << real.err);
  REQUIRE(real.exit_code == 0);
  const auto r = Json::parse(real.out);
  check_shape(r, "restored and verified");
  CHECK(r["nothing_to_do"] == false);
  check_steps(r["steps"], p, speed);
  CHECK(real.err.find("Set command(s) sent") == std::string::npos);  // the summary is the JSON
  CHECK(real.err.find("  set ") == std::string::npos);
  CHECK(test::schema_valid(dir, "report-restore.schema.json", real.out));
  // The journal keeps its DeviceNet steps: old and new as raw words (docs/audit.md).
  const auto rec = nlohmann::json::parse(test::slurp(dir / "lmcfg" / "journal.jsonl"));
  CHECK(rec["outcome"] == "restored and verified");
  REQUIRE(rec["steps"].size() == 2);
  CHECK(rec["steps"][0] == nlohmann::json{{"step", 1},
                                          {"action", "devicenet_set"},
                                          {"motor", "A"},
                                          {"command", "35h"},
                                          {"old", 2000},
                                          {"new", p},
                                          {"text", r["steps"][0]["text"]}});
  CHECK(test::run_tool_in(dir, "diff ctl.json drive " + sim.link()).exit_code == 0);

  auto again = test::run_tool_in(dir, "restore ctl.json --json --yes " + sim.link());
  INFO(again.out << again.err);
  CHECK(again.exit_code == 0);
  const auto n = Json::parse(again.out);
  check_shape(n, "nothing to do");
  CHECK(n["nothing_to_do"] == true);
  CHECK(n["steps"].empty());
  CHECK(n["devicenet"] == Json{{"unchanged", values}});
  CHECK(test::schema_valid(dir, "report-restore.schema.json", again.out));
}

}  // namespace

TEST_CASE(
    "DeviceNet §5.2 restore --json --dry-run and --json report the Set commands as restore "
    "steps, under each reading of the toggle rule",
    "[devicenet][cli][pty][toggle][json]") {
  for (const std::string rule : {"seed", "get-set-ignore", "module"})
    json_dry_run_then_restore(rule);
}

TEST_CASE("DeviceNet §5.2 restore --dry-run prints the plan of Set commands, writes nothing",
          "[devicenet][cli][pty]") {
  DnSim sim;
  test::ScratchDir d("dn-restore-dry");
  const auto& dir = d.path;
  REQUIRE(test::run_tool_in(dir, "backup " + sim.link() + " -q -o ctl.json").exit_code == 0);
  auto file = config::read_config_file((dir / "ctl.json").string());
  REQUIRE(file.ok());
  const std::size_t values = file->devicenet->values.size();
  test::change_two_values(sim);
  auto dry = test::run_tool_in(dir, "restore ctl.json --dry-run " + sim.link());
  INFO(dry.out << dry.err);
  CHECK(dry.exit_code == 0);
  CHECK(dry.out.rfind("restore plan for ctl.json: 2 Set command(s), " + std::to_string(values - 2) +
                          " value(s) already equal\n"
                          "  set 35h motor A: Controller P (34h): 4.6876 A/mm (raw 2000) -> ",
                      0) == 0);
  CHECK(dry.out.find("\n  set 51h motor B: Filter Maximal Speed (50h): 1000.02") !=
        std::string::npos);
  CHECK(dry.out.find("\nnote: " + kRuntime + ".\n") != std::string::npos);
  CHECK(!fs::exists(dir / "lmcfg" / "journal.jsonl"));
  CHECK(test::run_tool_in(dir, "diff ctl.json drive " + sim.link()).exit_code == 1);
}

TEST_CASE(
    "DeviceNet §5.2 a refused plan and a restore cut by a controller reset, as --json reports "
    "with the exit codes of the text runs",
    "[devicenet][cli][pty][json]") {
  test::ScratchDir d("dn-restore-json-bad");
  const auto& dir = d.path;
  {
    DnSim sim;
    test::backup_and_out_of_range(sim, dir);
    auto r = test::run_tool_in(dir, "restore bad.json --json --yes " + sim.link());
    INFO(r.out << r.err);
    CHECK(r.exit_code == 3);
    const auto j = Json::parse(r.out);
    CHECK(j["file"] == "bad.json");
    CHECK(j["outcome"] == "plan refused");
    CHECK(j["problems"] ==
          Json{"motor B: In Position Low Limit (48h): 11.71875 mm (raw 600) is outside Table "
               "5-1's range 2 to 511 (unit 0.01953 mm)"});
    CHECK(j["nothing_to_do"] == false);
    CHECK(j["steps"].empty());
    CHECK(r.err.find("REFUSED") == std::string::npos);
    CHECK(test::schema_valid(dir, "report-restore.schema.json", r.out));
    CHECK(!fs::exists(dir / "lmcfg" / "journal.jsonl"));
  }
  {
    DnSim sim({"--reset-after-sets", "3"});  // the two sets below, then the restore's first
    REQUIRE(test::run_tool_in(dir, "backup " + sim.link() + " -q -o ctl.json").exit_code == 0);
    test::change_two_values(sim);
    auto partial = test::run_tool_in(dir, "restore ctl.json --json --yes " + sim.link());
    INFO(partial.out << partial.err);
    CHECK(partial.exit_code == 4);
    const auto j = Json::parse(partial.out);
    CHECK(j["outcome"] == "failed");
    CHECK(j["steps"].size() == 2);
    const std::string error = j["error"];
    CHECK(error.find("0 of 2 Set command(s) done before it, the rest not sent: run the restore "
                     "again)") != std::string::npos);
    // After the read's notes (no encoder module on the simulated controller), the failure.
    const std::string last =
        "\nlmcfg restore: the controller is partially restored: " + error + "\n";
    REQUIRE(partial.err.size() > last.size());
    CHECK(partial.err.substr(partial.err.size() - last.size()) == last);
    CHECK(test::schema_valid(dir, "report-restore.schema.json", partial.out));
    const auto rec = nlohmann::json::parse(test::slurp(dir / "lmcfg" / "journal.jsonl"));
    CHECK(rec["outcome"] == "failed");
    CHECK(rec["exit_code"] == 4);
    CHECK(rec["error"] == error);
  }
}

}  // namespace tools_test_devicenet_restore_cli

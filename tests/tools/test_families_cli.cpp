// lmcfg backup, diff and restore end to end (LMCFG_TOOL_PATH, the built-in
// simulated drive --port sim:STATE.json) against a simulated B1100: it has no
// curve and no command table group ("not on B1100", LinRS 3V27 §11-§12) and
// answers both groups with C3h undefined message main ID (LinRS §16.1), as the
// simulator's family option plays it. With default options (no --family) the
// backup goes on without the groups and says so, the file's scope records
// them, diff finds the drive identical to its file, and the restore has
// nothing to write; a file that holds curves is refused with the reason.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_families_cli {

using namespace lmcfg;

namespace {

const std::string kFixtures = std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/";

nlohmann::json b1100() {
  auto j = nlohmann::json::parse(test::slurp(kFixtures + "commissioned-axis.json"));
  j["options"]["family"] = "B1100";
  return j;
}

bool has_line(const std::string& text, const std::string& line) {
  return ("\n" + text).find("\n" + line + "\n") != std::string::npos;
}

}  // namespace

TEST_CASE(
    "cli: a B1100 (C3h on the curve and command table groups) is backed up, diffed and restored "
    "with default options",
    "[families][cli]") {
  test::ScratchDir d("b1100-cli");
  const auto& dir = d.path;
  test::spit(dir / "b1100.json", b1100().dump(1));

  auto backup = test::run_tool_in(dir, "backup --port sim:b1100.json -o b1100-backup.json");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  CHECK(has_line(backup.err,
                 "backup: the drive has no curve group (it answers C3h undefined message main ID, "
                 "LinRS §16.1): curves not in the file; --family B1100 says so up front"));
  CHECK(has_line(backup.err,
                 "backup: the drive has no command table group (it answers C3h undefined message "
                 "main ID, LinRS §16.1): the command table not in the file; --family B1100 says "
                 "so up front"));
  const auto file = nlohmann::json::parse(test::slurp(dir / "b1100-backup.json"));
  CHECK(file.at("scope").at("curves") == false);
  CHECK(file.at("scope").at("command_table") == false);
  CHECK(file.at("scope").value("drive_lacks", nlohmann::json()) ==
        nlohmann::json::array({"curves", "command_table"}));

  auto diff = test::run_tool_in(dir, "diff b1100-backup.json drive --port sim:b1100.json");
  INFO(diff.out << diff.err);
  CHECK(diff.exit_code == 0);

  auto restore = test::run_tool_in(dir, "restore b1100-backup.json --port sim:b1100.json --yes");
  INFO(restore.out << restore.err);
  CHECK(restore.exit_code == 0);

  // --family states it up front: the same scope, no telegram of either group.
  auto named =
      test::run_tool_in(dir, "backup --port sim:b1100.json --family B1100 -o named.json -q");
  REQUIRE(named.exit_code == 0);
  const auto named_file = nlohmann::json::parse(test::slurp(dir / "named.json"));
  CHECK(named_file.at("scope") == file.at("scope"));
}

TEST_CASE(
    "cli: a file with curves and a command table restored onto a B1100 without --family is "
    "refused, saying the target has no such group",
    "[families][cli]") {
  test::ScratchDir d("b1100-cli-refused");
  const auto& dir = d.path;
  test::spit(dir / "axis.json", test::slurp(kFixtures + "commissioned-axis.json"));
  test::spit(dir / "b1100.json", b1100().dump(1));
  auto backup = test::run_tool_in(dir, "backup --port sim:axis.json -q -o axis-backup.json");
  REQUIRE(backup.exit_code == 0);
  const auto file = nlohmann::json::parse(test::slurp(dir / "axis-backup.json"));
  const auto curves = file.at("curves").size(), entries = file.at("command_table").size();
  REQUIRE(curves > 0);
  REQUIRE(entries > 0);

  auto refused = test::run_tool_in(dir, "restore axis-backup.json --port sim:b1100.json --yes");
  INFO(refused.out << refused.err);
  CHECK(refused.exit_code == 3);
  CHECK(has_line(refused.err, "  problem: the file holds " + std::to_string(entries) +
                                  " command table entries, but the target has no command table "
                                  "group (it answers C3h undefined message main ID, LinRS "
                                  "§16.1); --skip-incompatible restores the rest"));
  CHECK(has_line(refused.err, "  problem: the file holds " + std::to_string(curves) +
                                  " curve(s), but the target has no curve group (it answers C3h "
                                  "undefined message main ID, LinRS §16.1); --skip-incompatible "
                                  "restores the rest"));
}

}  // namespace tools_test_families_cli

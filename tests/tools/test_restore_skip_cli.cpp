// lmcfg restore and fleet restore end to end (LMCFG_TOOL_PATH, the built-in
// simulated drive --port sim:STATE.json): a file restored onto a drive of
// another firmware (refused, or --skip-incompatible: exit 7 with the skipped
// list), and the second pass for a command table whose flash differs from RAM.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "fleet/archive.hpp"
#include "sim/state_file.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_restore_skip_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

const std::string kFixtures = std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/";

nlohmann::json fixture(const std::string& name) {
  return nlohmann::json::parse(test::slurp(kFixtures + name));
}

nlohmann::json& param(nlohmann::json& state, const std::string& upid) {
  for (auto& p : state["parameters"])
    if (p["upid"] == upid) return p;
  FAIL("no parameter " << upid);
  throw std::logic_error("unreachable");
}

// The commissioned axis with its communication parameters at their defaults,
// so a restore without --include-comm reproduces it fully.
nlohmann::json axis() {
  auto j = fixture("commissioned-axis.json");
  for (const char* upid : {"200E", "206C"}) {
    auto& p = param(j, upid);
    p["rom"] = p["ram"] = p["default"];
  }
  return j;
}

// A used spare of another firmware: it lacks 1037h, has 13A6h as UINT32 (the
// axis: UINT16), allows 1022h only from 50 (the axis: 47) and has no ROM
// write bit on 3010h.
nlohmann::json other_firmware() {
  auto j = fixture("used-spare.json");
  auto& params = j["parameters"];
  for (auto it = params.begin(); it != params.end(); ++it)
    if ((*it)["upid"] == "1037") {
      params.erase(it);
      break;
    }
  param(j, "13A6")["type"] = "UINT32";
  param(j, "1022")["min"] = 50;
  param(j, "3010")["address_usage"] = "0007";
  return j;
}

std::map<std::string, std::uint32_t> modified(const fs::path& state) {
  auto s = sim::load_state(state.string());
  REQUIRE(s.ok());
  std::map<std::string, std::uint32_t> m;
  for (const auto& [upid, p] : s->params)
    if (p.modified()) m[hex(upid, 4)] = p.rom;
  return m;
}

// What the target cannot take, as the plan says it (names from the database).
const std::vector<std::string> kSkipped = {
    "MC 1022h RR Resistance: value 47 is below the minimum 50 (as the target reports it, §10 05h "
    "05h/06h)",
    "MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)",
    "MC 13A6h Position controller maximal current (MAX_I): type differs: the file has UINT16, "
    "the target has UINT32",
    "Appl 3010h: read-only on the target (the target's address usage 0007h has no ROM write bit)",
};

std::string lines(const std::string& head, const std::string& prefix) {
  std::string s = head;
  for (const auto& v : kSkipped) s += prefix + v + "\n";
  return s;
}

}  // namespace

TEST_CASE(
    "cli: restore onto another firmware refuses by default (exit 3), --skip-incompatible "
    "restores the rest, lists the skipped values and exits 7, again on a second run",
    "[restore][skip-incompatible][cli]") {
  test::ScratchDir d("restore-skip");
  const auto& dir = d.path;
  test::spit(dir / "axis.json", axis().dump(1));
  test::spit(dir / "spare.json", other_firmware().dump(1));
  auto backup = test::run_tool_in(dir, "backup --port sim:axis.json -q -o axis-backup.json");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  const auto spare_before = sim::load_state((dir / "spare.json").string());
  REQUIRE(spare_before.ok());

  auto refused = test::run_tool_in(dir, "restore axis-backup.json --port sim:spare.json --yes");
  CHECK(refused.exit_code == 3);
  CHECK(refused.out.empty());
  CHECK(refused.err == lines("restore refused: 4 problem(s), nothing written:\n", "  problem: "));
  auto spare_after = sim::load_state((dir / "spare.json").string());
  REQUIRE(spare_after.ok());
  CHECK(spare_after->params == spare_before->params);

  auto skip = test::run_tool_in(
      dir, "restore axis-backup.json --port sim:spare.json --yes --skip-incompatible");
  CHECK(skip.exit_code == 7);
  CHECK(skip.out == lines("skipped (the target cannot take them):\n", "  "));
  CHECK(skip.err.find("verified: the drive matches axis-backup.json except the skipped values") !=
        std::string::npos);
  auto want = modified(dir / "axis.json");
  for (const char* upid : {"1022", "1037", "13A6", "3010"}) want.erase(upid);
  want["2012"] = 32;  // the spare's communication value is kept (no --include-comm)
  CHECK(modified(dir / "spare.json") == want);

  auto again = test::run_tool_in(
      dir, "restore axis-backup.json --port sim:spare.json --yes --skip-incompatible --json");
  CHECK(again.exit_code == 7);
  const auto j = nlohmann::json::parse(again.out);
  CHECK(j["outcome"] == "nothing to do except the listed values");
  CHECK(j["nothing_to_do"] == true);
  REQUIRE(j["skipped_incompatible"].size() == 4);
  CHECK(j["skipped_incompatible"][0] ==
        nlohmann::json{{"layer", "MC"},
                       {"upid", "1022"},
                       {"name", "RR Resistance"},
                       {"reason_code", "out_of_range"},
                       {"reason",
                        "value 47 is below the minimum 50 (as the target reports it, "
                        "§10 05h 05h/06h)"}});
  std::vector<std::string> codes, upids;
  for (const auto& v : j["skipped_incompatible"]) {
    codes.push_back(v["reason_code"]);
    upids.push_back(v["upid"]);
  }
  CHECK(codes == std::vector<std::string>{"out_of_range", "upid_absent", "type_differs",
                                          "not_rom_writable"});
  CHECK(upids == std::vector<std::string>{"1022", "1037", "13A6", "3010"});
  CHECK(j["steps"].empty());
  auto text = test::run_tool_in(
      dir, "restore axis-backup.json --port sim:spare.json --yes --skip-incompatible");
  CHECK(text.exit_code == 7);
  CHECK(text.out ==
        "nothing to do: the drive already matches axis-backup.json except the skipped values\n" +
            lines("skipped (the target cannot take them):\n", "  "));
  CHECK(j["mismatches"].empty());
}

TEST_CASE("cli: a command table whose flash differs from RAM gets a second pass, said so",
          "[restore][flash][cli]") {
  test::ScratchDir d("restore-flash");
  const auto& dir = d.path;
  test::spit(dir / "axis.json", axis().dump(1));
  auto backup = test::run_tool_in(dir, "backup --port sim:axis.json -q -o axis-backup.json");
  REQUIRE(backup.exit_code == 0);
  auto target = axis();
  param(target, "13A2")["rom"] = 55;
  param(target, "13A2")["ram"] = 55;
  auto& ct = target["command_table"];
  ct["ram"] = ct["flash"];
  ct["flash"].erase(ct["flash"].size() - 1);  // entry 6 only in RAM
  test::spit(dir / "target.json", target.dump(1));

  auto r = test::run_tool_in(dir, "restore axis-backup.json --port sim:target.json --yes");
  INFO(r.err);
  CHECK(r.exit_code == 0);
  CHECK(r.err.find("restore: after the restart a table differed from the file (its flash held "
                   "another one): second pass, 4 step(s) (write, save to flash, start MC)\n") !=
        std::string::npos);
  auto after = sim::load_state((dir / "target.json").string());
  auto source = sim::load_state((dir / "axis.json").string());
  REQUIRE(after.ok());
  REQUIRE(source.ok());
  CHECK(after->ct_flash == source->ct_flash);
  auto json =
      test::run_tool_in(dir, "restore axis-backup.json --port sim:target.json --yes --json");
  CHECK(json.exit_code == 0);
  CHECK(nlohmann::json::parse(json.out)["outcome"] == "nothing to do");
}

TEST_CASE("cli: fleet restore --skip-incompatible records the skipped values in its commit",
          "[restore][skip-incompatible][fleet][cli]") {
  test::ScratchDir d("fleet-skip");
  const auto& dir = d.path;
  test::spit(dir / "s1.json", axis().dump(1));
  test::spit(dir / "plant.toml",
             "[[line]]\nname = \"bench\"\nport = \"sim:s1.json\"\n"
             "[[line.drive]]\nname = \"bench/a\"\nid = 0x11\n");
  auto first = test::run_tool_in(dir, "fleet backup plant.toml --archive arch");
  INFO(first.err);
  REQUIRE(first.exit_code == 0);
  auto archive = fleet::Archive::open((dir / "arch").string(), false);
  REQUIRE(archive.ok());
  const auto head = archive->resolve("HEAD").value();
  REQUIRE(head);

  test::spit(dir / "s1.json", other_firmware().dump(1));  // a replacement of another firmware
  auto refused =
      test::run_tool_in(dir, "fleet restore plant.toml --archive arch --drive bench/a --yes");
  CHECK(refused.exit_code == 3);
  CHECK(archive->resolve("HEAD").value()->id == head->id);

  auto r = test::run_tool_in(
      dir, "fleet restore plant.toml --archive arch --drive bench/a --yes --skip-incompatible");
  INFO(r.err);
  CHECK(r.exit_code == 7);
  const auto record = archive->resolve("HEAD").value();
  REQUIRE(record);
  CHECK(record->message == "fleet restore: bench/a <- bench/a.json at " + head->id.substr(0, 12) +
                               " (approved): restored except the listed values, verified\n\nline "
                               "bench (sim:s1.json), MACID 11h, 30 step(s)\n\n" +
                               lines("skipped (the target cannot take them):\n", "  ") +
                               "\nOperator: " + test::os_user() + "\n");
}

}  // namespace tools_test_restore_skip_cli

// The audit trail end to end (docs/audit.md): restore, set, default and undo
// on a simulated drive append one journal line each with who, why, the steps
// and the outcome; `lmcfg journal` shows them; a journal that cannot be
// written is a warning; fleet restore's record carries the trailers, read back
// with git itself; `fleet log` shows a position's history; require_reason.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <sstream>

#include "files.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_audit_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

const std::string kFixtures = std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/";

struct Rig : test::ScratchDir {
  explicit Rig(const std::string& name) : ScratchDir(name) {}
  test::ToolRun tool(const std::string& args) const { return test::run_tool_in(path, args); }
  fs::path journal() const { return path / "lmcfg" / "journal.jsonl"; }
  // The journal's records, oldest first.
  std::vector<nlohmann::ordered_json> records() const {
    std::vector<nlohmann::ordered_json> out;
    std::error_code ec;
    if (!fs::exists(journal(), ec)) return out;
    std::istringstream in(test::slurp(journal()));
    for (std::string line; std::getline(in, line);)
      out.push_back(nlohmann::ordered_json::parse(line));
    return out;
  }
  std::string git(const std::string& args) const {
    return test::shell_output("cd '" + path.string() + "' && TZ=UTC git " + args);
  }
};

std::vector<std::string> keys(const nlohmann::ordered_json& j) {
  std::vector<std::string> out;
  for (const auto& [k, v] : j.items()) out.push_back(k);
  return out;
}

bool iso_utc(const std::string& t) {
  return t.size() == 20 && t[4] == '-' && t[7] == '-' && t[10] == 'T' && t[13] == ':' &&
         t[16] == ':' && t[19] == 'Z';
}

// The sim line of two drives (the commissioned axis at MACIDs 11h and 12h),
// backed up into `arch`; bench/b then replaced by a factory-fresh drive.
void fleet_rig(const Rig& r, const std::string& head) {
  for (auto [file, id] : {std::pair{"s1.json", 0x11}, std::pair{"s2.json", 0x12}}) {
    auto j = nlohmann::json::parse(test::slurp(kFixtures + "commissioned-axis.json"));
    j["macid"] = id;
    // Communication parameters at their defaults: the MACID comes from the
    // state file, so the drive still answers as `id` after the restore's reset.
    for (auto& p : j["parameters"]) {
      const std::string upid = p["upid"];
      if (upid == "200E" || upid == "206C") p["rom"] = p["ram"] = p["default"];
    }
    test::spit(r.path / file, j.dump(1));
  }
  test::spit(r.path / "plant.toml",
             head +
                 "[[line]]\nname = \"bench\"\nport = \"sim:s1.json,s2.json\"\n"
                 "[[line.drive]]\nname = \"bench/a\"\nid = 0x11\n"
                 "[[line.drive]]\nname = \"bench/b\"\nid = 0x12\n");
  auto backup = r.tool("fleet backup plant.toml --archive arch -q");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  auto fresh = nlohmann::json::parse(test::slurp(r.path / "s2.json"));
  for (auto& p : fresh["parameters"]) p["rom"] = p["ram"] = p["default"];
  fresh["curves"] = nlohmann::json::array();
  fresh["command_table"] = nlohmann::json::array();
  test::spit(r.path / "s2.json", fresh.dump(1));
}

}  // namespace

TEST_CASE("audit cli: restore, set, default and undo each append one journal line",
          "[audit][journal][cli]") {
  Rig r("audit-cli");
  fs::copy_file(kFixtures + "used-spare.json", r.path / "spare.json");
  fs::copy_file(kFixtures + "commissioned-axis.json", r.path / "demo.json");
  REQUIRE(r.tool("backup --port sim:demo.json -q -o wrong.json").exit_code == 0);

  // Dry runs write nothing and record nothing.
  REQUIRE(r.tool("restore wrong.json --port sim:spare.json --dry-run").exit_code == 0);
  CHECK_FALSE(fs::exists(r.journal()));

  auto restored = r.tool(
      "restore wrong.json --port sim:spare.json --yes --json --reason 'replaced the motor' "
      "--ticket T-17");
  INFO(restored.err);
  REQUIRE(restored.exit_code == 0);
  const auto report = nlohmann::json::parse(restored.out);
  auto recs = r.records();
  REQUIRE(recs.size() == 1);
  const auto& rec = recs[0];
  CHECK(keys(rec) == std::vector<std::string>{"time", "who", "reason", "ticket", "command", "drive",
                                              "file", "steps", "outcome", "exit_code",
                                              "exit_category", "error", "undo"});
  CHECK(iso_utc(rec["time"]));
  CHECK(rec["who"] == test::os_user());
  CHECK(rec["reason"] == "replaced the motor");
  CHECK(rec["ticket"] == "T-17");
  CHECK(rec["command"] == "restore");
  CHECK(rec["drive"] == nlohmann::ordered_json{{"port", "sim:spare.json"}, {"id", "11h"}});
  CHECK(rec["file"] == "wrong.json");
  // The steps are the plan's, as restore --json reports them.
  REQUIRE(rec["steps"].size() > 3);
  CHECK(nlohmann::json(rec["steps"]) == report["steps"]);
  CHECK(rec["outcome"] == "restored and verified");
  CHECK(rec["exit_code"] == 0);
  CHECK(rec["exit_category"] == "ok");
  CHECK(rec["error"].is_null());
  CHECK(rec["undo"].get<std::string>() == report["undo"]["path"].get<std::string>());
  CHECK(fs::exists(rec["undo"].get<std::string>()));

  // Nothing to do: nothing written, nothing recorded.
  REQUIRE(r.tool("restore wrong.json --port sim:spare.json --yes").exit_code == 0);
  CHECK(r.records().size() == 1);

  auto set = r.tool("set 13A2 1234 --rom --stop-mc --port sim:spare.json --reason tuning");
  INFO(set.err);
  REQUIRE(set.exit_code == 0);
  recs = r.records();
  REQUIRE(recs.size() == 2);
  CHECK(recs[1]["command"] == "set");
  CHECK(recs[1]["who"] == test::os_user());
  CHECK(recs[1]["reason"] == "tuning");
  CHECK(recs[1]["ticket"].is_null());
  REQUIRE(recs[1]["steps"].size() == 1);
  CHECK(recs[1]["steps"][0]["action"] == "write_rom");
  CHECK(recs[1]["steps"][0]["upid"] == "13A2");
  CHECK(recs[1]["steps"][0]["new"]["raw"] == 1234);
  // The old ROM value, from the layer's modified list read for the undo record.
  CHECK(recs[1]["steps"][0]["old"]["raw"] == 40);
  CHECK(recs[1]["outcome"] == "written");
  CHECK(recs[1]["undo"].get<std::string>().ends_with("-set.json"));

  auto def = r.tool("default --layers appl --yes --port sim:spare.json --ticket T-18");
  INFO(def.err);
  REQUIRE(def.exit_code == 0);
  recs = r.records();
  REQUIRE(recs.size() == 3);
  CHECK(recs[2]["command"] == "default");
  CHECK(recs[2]["reason"].is_null());
  CHECK(recs[2]["ticket"] == "T-18");
  CHECK(nlohmann::json(recs[2]["steps"][0]) ==
        nlohmann::json{{"step", 1}, {"action", "default_layer"}, {"layer", "Appl"}});
  CHECK(recs[2]["outcome"] == "defaulted");

  auto undo = r.tool("undo --port sim:spare.json --yes --reason 'back to before'");
  INFO(undo.err);
  REQUIRE(undo.exit_code == 0);
  recs = r.records();
  REQUIRE(recs.size() == 4);
  CHECK(recs[3]["command"] == "undo");
  CHECK(recs[3]["reason"] == "back to before");
  CHECK(recs[3]["file"].get<std::string>().ends_with("-default.json"));

  // lmcfg journal: newest first; --port filters; --json gives the records.
  auto shown = r.tool("journal");
  CHECK(shown.exit_code == 0);
  const auto undo_at =
      shown.out.find("  undo  sim:spare.json 11h  " + test::os_user() +
                     ": restored and verified (exit 0)\n    why: back to before\n");
  const auto restore_at = shown.out.find("  restore  sim:spare.json 11h  " + test::os_user() +
                                         ": restored and verified (exit 0)\n"
                                         "    why: replaced the motor (ticket T-17)\n");
  CHECK(undo_at != std::string::npos);
  CHECK(restore_at != std::string::npos);
  CHECK(undo_at < restore_at);
  CHECK(shown.out.find("    why: - (ticket T-18)\n") != std::string::npos);
  auto limited = r.tool("journal --json --port sim:spare.json --limit 2");
  REQUIRE(limited.exit_code == 0);
  const auto lj = nlohmann::json::parse(limited.out);
  CHECK(lj["journal"] == r.journal().string());
  REQUIRE(lj["records"].size() == 2);
  CHECK(lj["records"][0]["command"] == "undo");
  CHECK(lj["records"][1]["command"] == "default");
  auto other = r.tool("journal --port sim:other.json");
  CHECK(other.exit_code == 0);
  CHECK(other.out == "no writes recorded for sim:other.json in " + r.journal().string() + "\n");
  auto other_id = r.tool("journal --port sim:spare.json --id 0x12 --json");
  CHECK(nlohmann::json::parse(other_id.out)["records"].empty());
}

TEST_CASE("audit cli: a journal that cannot be written is a warning, never a failed restore",
          "[audit][journal][cli]") {
  Rig r("audit-cli-nojournal");
  fs::copy_file(kFixtures + "used-spare.json", r.path / "spare.json");
  fs::copy_file(kFixtures + "commissioned-axis.json", r.path / "demo.json");
  REQUIRE(r.tool("backup --port sim:demo.json -q -o wrong.json").exit_code == 0);
  fs::create_directories(r.journal());  // a directory where the journal belongs
  auto restored = r.tool("restore wrong.json --port sim:spare.json --yes --reason x");
  CHECK(restored.exit_code == 0);
  CHECK(restored.err.find("lmcfg restore: warning: not recorded in the journal: journal " +
                          r.journal().string() + ": cannot open: Is a directory\n") !=
        std::string::npos);
  CHECK(r.tool("diff wrong.json drive --port sim:spare.json --ignore-metadata --ignore-unit -q")
            .exit_code == 0);
}

TEST_CASE("audit cli: fleet restore records who and why as trailers, fleet log shows them",
          "[audit][fleet][cli]") {
  Rig r("audit-fleet");
  fleet_rig(r, "");
  const std::string backup_id = r.git("-C arch rev-parse HEAD");
  auto restore = r.tool(
      "fleet restore plant.toml --archive arch --drive bench/b --yes --reason 'motor replaced' "
      "--ticket T-17");
  INFO(restore.err);
  REQUIRE(restore.exit_code == 0);
  // git itself reads the record's trailers.
  CHECK(r.git("-C arch log -1 --format=%\\(trailers\\)") ==
        "Operator: " + test::os_user() + "\nReason: motor replaced\nTicket: T-17\n\n");
  CHECK(r.git("-C arch log -1 --format=%s") == "fleet restore: bench/b <- bench/b.json at " +
                                                   backup_id.substr(0, 12) +
                                                   " (approved): restored and verified\n");

  // The journal has it too, with the position.
  const auto recs = r.records();
  REQUIRE(recs.size() == 1);
  CHECK(recs[0]["command"] == "fleet-restore");
  CHECK(recs[0]["drive"] == nlohmann::ordered_json{{"port", "sim:s1.json,s2.json"},
                                                   {"id", "12h"},
                                                   {"position", "bench/b"}});
  CHECK(recs[0]["file"] == "bench/b.json@" + backup_id.substr(0, 12));
  CHECK(recs[0]["reason"] == "motor replaced");

  // fleet log: the restore record and the backup, newest first, as git has them.
  auto log = r.tool("fleet log bench/b --archive arch");
  INFO(log.err);
  REQUIRE(log.exit_code == 0);
  const std::string dates =
      r.git("-C arch log -2 --date=format-local:%Y-%m-%dT%H:%M:%SZ --format='%cd %h' --abbrev=12");
  std::istringstream in(dates);
  std::string restore_time, restore_id, backup_time, backup_id12;
  in >> restore_time >> restore_id >> backup_time >> backup_id12;
  const std::string author = r.git("-C arch log -1 --format=%an " + backup_id);
  CHECK(log.out ==
        restore_time + "  " + restore_id + "  restore  " + test::os_user() +
            "\n    fleet restore: bench/b <- bench/b.json at " + backup_id.substr(0, 12) +
            " (approved): restored and verified\n    why: motor replaced (ticket T-17)\n"
            "\n" +
            backup_time + "  " + backup_id12 + "  backup  " + author.substr(0, author.size() - 1) +
            "\n    fleet backup: 0 changed, 0 unchanged, 2 new, 0 failed\n");
  auto json = r.tool("fleet log bench/b --archive arch --inventory plant.toml --json");
  REQUIRE(json.exit_code == 0);
  const auto j = nlohmann::json::parse(json.out);
  REQUIRE(j.size() == 2);
  CHECK(j[0]["commit"] == r.git("-C arch rev-parse HEAD").substr(0, 40));
  CHECK(j[0]["time"] == restore_time);
  CHECK(j[0]["kind"] == "restore");
  CHECK(j[0]["who"] == test::os_user());
  CHECK(j[0]["reason"] == "motor replaced");
  CHECK(j[0]["ticket"] == "T-17");
  CHECK(j[1]["kind"] == "backup");
  CHECK(j[1]["reason"].is_null());
  CHECK(j[1]["subject"] == "fleet backup: 0 changed, 0 unchanged, 2 new, 0 failed");
  // The other position's history has its backup only.
  auto other = r.tool("fleet log bench/a --archive arch --json");
  CHECK(nlohmann::json::parse(other.out).size() == 1);
  auto none = r.tool("fleet log bench/zz --archive arch");
  CHECK(none.exit_code == 0);
  CHECK(none.out == "no history of bench/zz in the archive\n");
  auto unknown = r.tool("fleet log bench/zz --archive arch --inventory plant.toml");
  CHECK(unknown.exit_code == 2);
  CHECK(unknown.err == "lmcfg fleet log: plant.toml: no drive named 'bench/zz' in the inventory\n");
  auto badname = r.tool("fleet log ../x --archive arch");
  CHECK(badname.exit_code == 2);
}

TEST_CASE("audit cli: require_reason = true refuses a fleet restore without --reason",
          "[audit][fleet][cli]") {
  Rig r("audit-require");
  fleet_rig(r, "require_reason = true\n");
  const std::string head = r.git("-C arch rev-parse HEAD");
  const std::string drive = test::slurp(r.path / "s2.json");
  auto refused = r.tool("fleet restore plant.toml --archive arch --drive bench/b --yes");
  CHECK(refused.exit_code == 2);
  CHECK(refused.err ==
        "lmcfg fleet restore: plant.toml: require_reason = true: a restore needs --reason TEXT "
        "(why this drive is written; recorded in the archive and the journal); nothing written\n");
  CHECK(r.git("-C arch rev-parse HEAD") == head);
  CHECK(test::slurp(r.path / "s2.json") == drive);
  CHECK_FALSE(fs::exists(r.journal()));
  // A ticket alone is not a reason.
  CHECK(r.tool("fleet restore plant.toml --archive arch --drive bench/b --yes --ticket T-1")
            .exit_code == 2);
  auto ok = r.tool("fleet restore plant.toml --archive arch --drive bench/b --yes --reason spare");
  INFO(ok.err);
  CHECK(ok.exit_code == 0);
  CHECK(r.git("-C arch log -1 --format=%\\(trailers:key=Reason,valueonly\\)") == "spare\n\n");
}

}  // namespace tools_test_audit_cli

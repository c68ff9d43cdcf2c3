// lmcfg undo end to end: the wrong file restored onto a simulated drive, then
// `lmcfg undo` brings it back; the records of default and set --rom; the
// listing; --no-undo; a record that cannot be saved refuses the write.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "files.hpp"
#include "subprocess.hpp"
#include "trace_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_undo_cli {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

struct Rig : test::ScratchDir {
  Rig() : ScratchDir("undo-cli") {
    fs::copy_file(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/used-spare.json",
                  path / "spare.json");
    fs::copy_file(std::string(LMCFG_SOURCE_DIR) + "/tests/fixtures/sim/commissioned-axis.json",
                  path / "demo.json");
  }
  test::ToolRun tool(const std::string& args) const { return test::run_tool_in(path, args); }
  fs::path drive_dir() const { return path / "lmcfg" / "undo" / "sim_spare.json-11h"; }
  // The drive's records, oldest first.
  std::vector<fs::path> records() const {
    std::vector<fs::path> out;
    std::error_code ec;
    if (!fs::is_directory(drive_dir(), ec)) return out;
    for (const auto& e : fs::directory_iterator(drive_dir())) out.push_back(e.path());
    std::sort(out.begin(), out.end());
    return out;
  }
  // The spare compared with `file` (the diff of a backup taken before).
  int diff_with(const std::string& file) const {
    return tool("diff " + file + " drive --port sim:spare.json --ignore-metadata --ignore-unit -q")
        .exit_code;
  }
};

std::string saved_line(const fs::path& record, const std::string& port = "sim:spare.json") {
  return "undo: saved the target's previous values to " + record.string() +
         "; to put them back: lmcfg undo --port " + port + " --id 0x11\n";
}

bool contains(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

}  // namespace

TEST_CASE("undo cli: the wrong file restored onto a drive, lmcfg undo brings it back",
          "[undo][cli]") {
  Rig r;
  REQUIRE(r.tool("backup --port sim:spare.json -q -o before.json").exit_code == 0);
  REQUIRE(r.tool("backup --port sim:demo.json -q -o wrong.json").exit_code == 0);

  auto restored = r.tool("restore wrong.json --port sim:spare.json --yes");
  INFO(restored.err);
  REQUIRE(restored.exit_code == 0);
  auto recs = r.records();
  REQUIRE(recs.size() == 1);
  CHECK(recs[0].filename().string().ends_with("-restore.json"));
  CHECK(contains(restored.err, saved_line(recs[0])));
  CHECK(r.diff_with("before.json") == 1);
  // The record is an ordinary configuration file: the spare before the restore.
  CHECK(r.tool("diff before.json " + recs[0].string() + " --ignore-metadata --ignore-unit -q")
            .exit_code == 0);

  // The listing: per drive, newest first.
  auto list = r.tool("undo --list");
  CHECK(list.exit_code == 0);
  auto listed = r.tool("undo --list --json");
  REQUIRE(listed.exit_code == 0);
  const auto j = nlohmann::json::parse(listed.out);
  REQUIRE(j["records"].size() == 1);
  const auto& rec = j["records"][0];
  CHECK(rec["drive"] == "sim_spare.json-11h");
  CHECK(rec["command"] == "restore");
  CHECK(rec["path"] == recs[0].string());
  CHECK(list.out == "sim_spare.json-11h:\n  " + rec["time"].get<std::string>() +
                        "  restore        " + recs[0].string() + "\n      " +
                        rec["holds"].get<std::string>() + "\n");
  CHECK(rec["holds"] ==
        "OS 1 parameter, MC 6 parameters, Intf 1 parameter, Appl 2 parameters, 1 curve, 2 "
        "command table entries");

  // Undo: the normal restore path, with a record of its own first.
  auto undone = r.tool("undo --port sim:spare.json --yes");
  INFO(undone.err);
  CHECK(undone.exit_code == 0);
  CHECK(undone.err.starts_with("undo: restoring " + recs[0].string() + "\n"));
  recs = r.records();
  REQUIRE(recs.size() == 2);
  CHECK(recs[1].filename().string().ends_with("-undo.json"));
  CHECK(contains(undone.err, saved_line(recs[1])));
  CHECK(r.diff_with("before.json") == 0);

  // An undo can be undone: the newest record is the undo's own.
  CHECK(r.tool("undo --port sim:spare.json --yes -q").exit_code == 0);
  CHECK(r.diff_with("wrong.json") == 0);

  // No terminal, no --yes: refused like restore, nothing written.
  const auto n = r.records().size();
  auto refused = r.tool("undo --port sim:spare.json");
  CHECK(refused.exit_code == 2);
  CHECK(r.records().size() == n);
  CHECK(r.diff_with("wrong.json") == 0);
}

TEST_CASE("undo cli: exact messages and exit codes", "[undo][cli]") {
  Rig r;
  auto none = r.tool("undo --port sim:spare.json --id 0x22");
  CHECK(none.exit_code == 2);
  CHECK(none.err == "lmcfg undo: no undo record of drive 0x22 on sim:spare.json in " +
                        (r.path / "lmcfg" / "undo" / "sim_spare.json-22h").string() +
                        " (lmcfg undo --list shows every record)\n");
  auto no_port = r.tool("undo");
  CHECK(no_port.exit_code == 2);
  CHECK(no_port.err ==
        "lmcfg undo: --port is required: the drive to put the record back onto (or --list to see "
        "the records)\n");
  auto empty = r.tool("undo --list");
  CHECK(empty.exit_code == 0);
  CHECK(empty.out == "no undo records in " + (r.path / "lmcfg" / "undo").string() + "\n");
  auto missing = r.tool("undo nowhere.json --port sim:spare.json --yes");
  CHECK(missing.exit_code == 2);
  CHECK(contains(missing.err, "nowhere.json"));

  // A record that cannot be saved: exit 2 with the path and the OS error, no write telegram.
  REQUIRE(r.tool("backup --port sim:demo.json -q -o wrong.json").exit_code == 0);
  fs::create_directories(r.path / "lmcfg");
  test::spit(r.path / "lmcfg" / "undo", "a file where the directory belongs");
  auto blocked = r.tool("restore wrong.json --port sim:spare.json --yes -q --trace t.trace");
  CHECK(blocked.exit_code == 2);
  CHECK(blocked.err == "lmcfg restore: cannot save the undo record: " +
                           (r.path / "lmcfg" / "undo" / "sim_spare.json-11h").string() +
                           ": cannot create the directory: Not a directory; nothing written "
                           "(--no-undo writes without it)\n");
  CHECK(test::traced_writes(r.path / "t.trace") == 0);
  // --no-undo writes without a record.
  auto without = r.tool("restore wrong.json --port sim:spare.json --yes -q --no-undo");
  CHECK(without.exit_code == 0);
  CHECK(without.err.empty());
  CHECK(r.diff_with("wrong.json") == 0);
}

TEST_CASE("undo cli: restore --json lists the record, --no-undo saves none", "[undo][cli]") {
  Rig r;
  REQUIRE(r.tool("backup --port sim:demo.json -q -o wrong.json").exit_code == 0);
  auto dry = r.tool("restore wrong.json --port sim:spare.json --dry-run");
  CHECK(dry.exit_code == 0);
  CHECK(r.records().empty());
  auto j = r.tool("restore wrong.json --port sim:spare.json --yes --json");
  REQUIRE(j.exit_code == 0);
  const auto out = nlohmann::json::parse(j.out);
  const auto recs = r.records();
  REQUIRE(recs.size() == 1);
  CHECK(out["undo"]["path"] == recs[0].string());
  CHECK(out["undo"]["command"] == "lmcfg undo --port sim:spare.json --id 0x11");
  CHECK_FALSE(contains(j.err, "undo: saved"));
  // Nothing to do: nothing written, no record.
  CHECK(r.tool("restore wrong.json --port sim:spare.json --yes -q").exit_code == 0);
  CHECK(r.records().size() == 1);
}

TEST_CASE("undo cli: default and set --rom save records that undo puts back", "[undo][cli]") {
  Rig r;
  REQUIRE(r.tool("backup --port sim:spare.json -q -o before.json").exit_code == 0);

  auto d = r.tool("default --port sim:spare.json --layers mc --curves --ct --yes");
  INFO(d.err);
  REQUIRE(d.exit_code == 0);
  auto recs = r.records();
  REQUIRE(recs.size() == 1);
  CHECK(recs[0].filename().string().ends_with("-default.json"));
  CHECK(d.err.starts_with(saved_line(recs[0])));
  CHECK(r.diff_with("before.json") == 1);
  auto listed = nlohmann::json::parse(r.tool("undo --list --json").out);
  CHECK(listed["records"][0]["holds"].get<std::string>().starts_with("MC "));
  CHECK(r.tool("undo --port sim:spare.json --yes -q").exit_code == 0);
  CHECK(r.diff_with("before.json") == 0);

  // set --rom of a value at its default (101Eh 780): the record holds the MC
  // layer's modified list; undo sends 101Eh back to its default.
  auto s = r.tool("set 101E 800 --rom --stop-mc --port sim:spare.json");
  INFO(s.err);
  REQUIRE(s.exit_code == 0);
  recs = r.records();
  REQUIRE(recs.size() == 3);  // default, undo, set
  CHECK(recs[2].filename().string().ends_with("-set.json"));
  CHECK(contains(s.err, saved_line(recs[2])));
  CHECK(r.diff_with("before.json") == 1);
  auto js = r.tool("set 101E 801 --rom --stop-mc --port sim:spare.json --json");
  REQUIRE(js.exit_code == 0);
  CHECK(nlohmann::json::parse(js.out)["undo"]["path"] == r.records().back().string());
  CHECK(r.tool("undo " + recs[2].string() + " --port sim:spare.json --yes -q").exit_code == 0);
  CHECK(r.diff_with("before.json") == 0);
  // A RAM write vanishes at the next reset: no record.
  const auto n = r.records().size();
  CHECK(r.tool("set 101E 800 --port sim:spare.json -q").exit_code == 0);
  CHECK(r.records().size() == n);
  // set --rom --no-undo: none either.
  CHECK(r.tool("set 101E 800 --rom --stop-mc --no-undo --port sim:spare.json -q").exit_code == 0);
  CHECK(r.records().size() == n);
}

TEST_CASE("undo cli: the rotation keeps the newest 10 records of a drive", "[undo][cli]") {
  Rig r;
  for (int i = 0; i < 11; ++i) {
    auto s =
        r.tool("set 101E " + std::to_string(800 + i) + " --rom --stop-mc --port sim:spare.json -q");
    REQUIRE(s.exit_code == 0);
  }
  const auto recs = r.records();
  CHECK(recs.size() == 10);
  auto listed = nlohmann::json::parse(r.tool("undo --list --json").out);
  CHECK(listed["records"].size() == 10);
}

}  // namespace tools_test_undo_cli

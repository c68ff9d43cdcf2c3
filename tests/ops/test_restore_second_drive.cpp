// A restore onto the second drive of a two-drive simulated RS485 line
// (sim:A,B). Both drives are the commissioned axis, which takes its MACID "By
// Parameter": LinRS §15 MACID Source Select "By Parameter: Take the value of
// MACID Parameter Value", and LinRS §9 "A Reset command or Power cycle
// restarts all SW instances". The restore's reset (§13.1) therefore puts the
// drive on the MACID its ROM 2076h holds.
#include <catch2/catch.hpp>
#include <filesystem>
#include <nlohmann/json.hpp>

#include "config/config_io.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/restore_run.hpp"
#include "serve_rig.hpp"
#include "sim/state_file.hpp"
#include "subprocess.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_second_drive {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

// The ROM value of `upid` in a state file.
std::uint32_t rom_in(const fs::path& state, std::uint16_t upid) {
  auto s = sim::load_state(state.string());
  REQUIRE(s.ok());
  const auto it = s->params.find(upid);
  REQUIRE(it != s->params.end());
  return it->second.rom;
}

// A drive at MACID `id` whose ROM still selects MACID 11h (2076h at the
// fixture's 17): 2076h changed without a restart since, as far as the drive
// tells.
void write_axis_leaving_11h(const fs::path& path, int id, const std::string& upid, int value) {
  test::write_axis(path, id, upid, value);
  auto j = nlohmann::json::parse(test::slurp(path));
  for (auto& p : j["parameters"])
    if (p["upid"] == "2076") p["rom"] = p["ram"] = 0x11;
  test::spit(path, j.dump(1));
}

struct Line {
  test::ScratchDir dir{"second-drive"};
  fs::path a = dir.path / "a.json", b = dir.path / "b.json";
  std::string port() const { return "sim:" + a.string() + "," + b.string(); }

  std::unique_ptr<link::Session> open(std::uint8_t id) const {
    link::LinkSpec lo;
    lo.port = *link::parse_port(port());
    lo.client.id = id;
    auto s = link::open_session(lo);
    REQUIRE(s.ok());
    return std::move(s).value();
  }
  // A backup of the drive at `id`, then the line closed (saved).
  config::DriveConfig backup(std::uint8_t id, const db::Database& db) const {
    auto s = open(id);
    auto cfg = ops::backup(s->client(), ops::BackupOptions{}, db);
    REQUIRE(cfg.ok());
    REQUIRE(s->close().ok());
    return std::move(cfg).value();
  }
};

}  // namespace

TEST_CASE("restore: the second drive of a two-drive sim line (LinRS §13.1, §15)",
          "[restore][multidrop]") {
  auto db = test::built_database();
  REQUIRE(db);
  Line line;
  test::write_axis(line.a, 0x11);
  test::write_axis(line.b, 0x12);
  const auto file = line.backup(0x12, *db);
  // 13A2h (P Gain Position Controller Set A) tuned on b after the backup: 40 -> 55.
  test::write_axis(line.b, 0x12, "13A2", 55);
  const std::string a_before = test::slurp(line.a);

  auto s = line.open(0x12);
  ops::RestoreRunOptions ro;
  const auto out = ops::run_restore(*s, file, *db, ro);
  INFO((out.error ? out.error->message : std::string()));
  CHECK(ops::outcome_name(out) == "restored and verified");
  CHECK_FALSE(out.relink);
  CHECK(s->client().options().id == 0x12);
  REQUIRE(s->close().ok());
  CHECK(rom_in(line.b, 0x13A2) == 40);
  auto b_after = sim::load_state(line.b.string());
  REQUIRE(b_after.ok());
  CHECK(b_after->macid == 0x12);
  CHECK(test::slurp(line.a) == a_before);  // the first drive heard nothing it acted on
}

TEST_CASE(
    "restore: a drive whose ROM selects another MACID than it answers at is refused before any "
    "write (LinRS §15)",
    "[restore][multidrop]") {
  auto db = test::built_database();
  REQUIRE(db);
  Line line;
  test::write_axis(line.a, 0x11);
  write_axis_leaving_11h(line.b, 0x12, "", 0);
  const auto file = line.backup(0x12, *db);
  write_axis_leaving_11h(line.b, 0x12, "13A2", 55);

  auto s = line.open(0x12);
  ops::RestoreRunOptions ro;
  const auto out = ops::run_restore(*s, file, *db, ro);
  CHECK(ops::outcome_name(out) == "plan refused");
  CHECK_FALSE(out.written);
  REQUIRE(out.plan.problems.size() == 1);
  CHECK(out.plan.problems[0] ==
        "the drive answers at MACID 12h, but its ROM selects MACID 11h (MACID 11h: 206Ch = By "
        "Parameter, 2076h MACID Parameter Value = 17 (its default)): the restore's reset would "
        "move it to 11h, where another drive of the line may answer. Write the MACID it keeps "
        "first ('lmcfg set 2076h 18 --rom --include-comm'), or, on a line of its own, restore "
        "with --include-comm to follow it");
  CHECK(out.plan.steps.empty());
  REQUIRE(s->close().ok());
  CHECK(rom_in(line.b, 0x13A2) == 55);  // nothing written

  // With --include-comm the tool follows the drive to 11h; on a line of its own
  // it is found there.
  test::ScratchDir solo("second-drive-solo");
  write_axis_leaving_11h(solo.path / "b.json", 0x12, "13A2", 55);
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:" + (solo.path / "b.json").string());
  lo.client.id = 0x12;
  auto alone = link::open_session(lo);
  REQUIRE(alone.ok());
  ro.restore.include_comm = true;
  const auto followed = ops::run_restore(**alone, file, *db, ro);
  INFO((followed.error ? followed.error->message : std::string()));
  CHECK(ops::outcome_name(followed) == "restored and verified");
  REQUIRE(followed.relink);
  CHECK(followed.relink->summary == "the drive answers at 57600 Bd, MACID 11h, checksum none");
  REQUIRE((*alone)->close().ok());
  CHECK(rom_in(solo.path / "b.json", 0x13A2) == 40);
}

TEST_CASE("restore: lmcfg restore --id 0x12 onto the second drive of sim:a.json,b.json",
          "[restore][multidrop][e2e]") {
  Line line;
  test::write_axis(line.a, 0x11);
  test::write_axis(line.b, 0x12);
  const std::string port = " --port sim:a.json,b.json --id 0x12";
  auto backup = test::run_tool_in(line.dir.path, "backup" + port + " -o b-backup.json");
  INFO(backup.err);
  REQUIRE(backup.exit_code == 0);
  auto set = test::run_tool_in(line.dir.path, "set 13A2h 55 --rom --yes" + port);
  INFO(set.err);
  REQUIRE(set.exit_code == 0);
  REQUIRE(rom_in(line.b, 0x13A2) == 55);

  auto restore = test::run_tool_in(line.dir.path, "restore --yes b-backup.json" + port);
  INFO(restore.err);
  CHECK(restore.exit_code == 0);
  CHECK(rom_in(line.b, 0x13A2) == 40);
  CHECK(rom_in(line.a, 0x13A2) == 40);

  // The same line with b's ROM still selecting 11h: refused (exit 3), nothing written.
  write_axis_leaving_11h(line.b, 0x12, "13A2", 55);
  auto refused = test::run_tool_in(line.dir.path, "restore --yes b-backup.json" + port);
  CHECK(refused.exit_code == 3);
  CHECK(refused.err.find("the drive answers at MACID 12h, but its ROM selects MACID 11h") !=
        std::string::npos);
  CHECK(rom_in(line.b, 0x13A2) == 55);
}

}  // namespace ops_test_restore_second_drive

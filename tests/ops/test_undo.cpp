// Undo records (ops/undo.hpp) against the simulated drive, in process: the
// record of a restore holds the target's previous state in the file's scope,
// restoring it brings the drive back, the rotation keeps 10, and a restore
// without undo leaves no record.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <map>

#include "../../bench/wire_workloads.hpp"
#include "config/config_io.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "files.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/factory_reset.hpp"
#include "ops/restore.hpp"
#include "ops/restore_run.hpp"
#include "ops/undo.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_undo {

using namespace lmcfg;
namespace fs = std::filesystem;

namespace {

// What a configuration holds, without identity and display fields: UPID and
// value per layer in scope, curves and command table entries.
struct Content {
  std::map<int, std::map<std::uint16_t, std::uint32_t>> layers;
  std::vector<config::Curve> curves;
  std::vector<config::CtEntry> ct;
  bool operator==(const Content&) const = default;
};

Content content_of(const config::DriveConfig& cfg) {
  Content c;
  for (int layer = 1; layer <= 4; ++layer) {
    if (!cfg.scope.layers[static_cast<std::size_t>(layer - 1)]) continue;
    auto& m = c.layers[layer];
    for (const auto& p : cfg.layer(layer)) m[p.upid] = p.value;
  }
  if (cfg.scope.curves) c.curves = cfg.curves;
  if (cfg.scope.command_table) c.ct = cfg.ct_entries;
  return c;
}

config::DriveConfig read_back(client::Client& c) {
  ops::BackupOptions bo;
  bo.ask_drive = false;
  auto cfg = ops::backup(c, bo, db::Database::empty());
  REQUIRE(cfg.ok());
  return std::move(cfg).value();
}

config::DriveConfig demo_backup() {
  test::SimRig demo("commissioned-axis.json");
  return read_back(*demo.client);
}

// Plan, execute, verify: the restore without the tool.
void restore(client::Client& c, const config::DriveConfig& file, const ops::RestoreOptions& ro) {
  auto plan = ops::plan_restore(c, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  REQUIRE(ops::execute_plan(c, *plan, ro).ok());
  auto v = ops::verify_restore(c, *plan, ro);
  REQUIRE(v.ok());
  for (const auto& m : v->mismatches) UNSCOPED_INFO(m);
  CHECK(v->ok());
}

// A session on a simulated drive, as link::open_session makes one.
std::unique_ptr<link::Session> sim_session(std::shared_ptr<sim::Drive> drive) {
  link::LinkSpec lo;
  lo.port = *link::parse_port("sim:undo");
  lo.client.id = drive->macid();
  transport::OpenedLink opened;
  opened.link = std::make_unique<sim::SimLink>(std::move(drive));
  return std::make_unique<link::Session>(lo, lo.serial, std::move(opened), std::nullopt);
}

std::size_t files_in(const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(dir, ec)) return 0;
  std::size_t n = 0;
  for (const auto& e : fs::recursive_directory_iterator(dir))
    if (e.is_regular_file()) ++n;
  return n;
}

}  // namespace

TEST_CASE(
    "undo: a restore's record is the target's previous state in scope, restoring it "
    "brings the drive back",
    "[undo]") {
  const auto file = demo_backup();
  test::SimRig rig("used-spare.json");
  const auto before = read_back(*rig.client);
  const auto flash_before = rig.drive->state();
  ops::RestoreOptions ro;
  ro.include_comm = true;  // no database: every parameter is restored, as in the perf test

  const auto t0 = rig.sim().stats().request_telegrams;
  auto plan = ops::plan_restore(*rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  const auto t_plan = rig.sim().stats().request_telegrams;
  auto record = ops::undo_config_from_plan(*rig.client, *plan, file.scope, db::Database::empty());
  REQUIRE(record.ok());
  const auto t_record = rig.sim().stats().request_telegrams;
  // Only the data blocks of curves the restore replaces or deletes, where the
  // plan stopped at their sizes or info block, are read.
  const auto extra = t_record - t_plan;
  INFO("plan " << (t_plan - t0) << " telegrams, record " << extra);
  CHECK(extra > 0);
  CHECK(content_of(*record) == content_of(before));
  CHECK(record->scope.layers == file.scope.layers);
  CHECK(record->scope.curves == file.scope.curves);
  CHECK(record->scope.command_table == file.scope.command_table);

  REQUIRE(ops::execute_plan(*rig.client, *plan, ro).ok());
  REQUIRE(content_of(read_back(*rig.client)) == content_of(file));

  // The record as a file, read back as `lmcfg restore` reads it.
  test::ScratchDir dir("undo-record");
  const ops::UndoOptions uo{true, dir.path, "/dev/ttyUSB0", 0x11, "restore", ops::kUndoKeep};
  auto saved = ops::save_undo(uo, *record, db::Database::empty());
  REQUIRE(saved.ok());
  CHECK(saved->command == "lmcfg undo --port /dev/ttyUSB0 --id 0x11");
  CHECK(saved->path.parent_path() == dir.path / "_dev_ttyUSB0-11h");
  auto loaded = config::read_config_file(saved->path);
  REQUIRE(loaded.ok());
  CHECK(content_of(*loaded) == content_of(before));

  restore(*rig.client, *loaded, ro);
  CHECK(content_of(read_back(*rig.client)) == content_of(before));
  // Flash too: the tables the spare had are saved again.
  CHECK(rig.drive->state().curves_flash == flash_before.curves_flash);
  CHECK(rig.drive->state().ct_flash == flash_before.ct_flash);
}

TEST_CASE("undo: a record costs a few telegrams on the demo restores (docs/performance.md)",
          "[undo][perf]") {
  // The file of tests/ops/test_perf_telegrams.cpp: types and defaults asked from the drive.
  test::SimRig source("commissioned-axis.json");
  auto backup = ops::backup(*source.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(backup.ok());
  const auto& file = *backup;
  auto spare = sim::load_state(test::sim_fixture("used-spare.json"));
  auto demo = sim::load_state(test::sim_fixture("commissioned-axis.json"));
  REQUIRE(spare.ok());
  REQUIRE(demo.ok());
  const std::pair<const char*, sim::DriveState> targets[] = {
      {"a used spare", *spare}, {"a factory-fresh unit", benchwire::factory_fresh(*demo)}};
  for (const auto& [name, state] : targets) {
    auto drive = std::make_shared<sim::Drive>(state);
    sim::SimLink link(drive);
    client::LinrsClient c(link, client::ClientOptions{});
    ops::RestoreOptions ro;
    ro.include_comm = true;  // as tests/ops/test_perf_telegrams.cpp
    auto plan = ops::plan_restore(c, file, db::Database::empty(), ro);
    REQUIRE(plan.ok());
    const auto t_plan = link.stats().request_telegrams;
    auto record = ops::undo_config_from_plan(c, *plan, file.scope, db::Database::empty());
    REQUIRE(record.ok());
    const auto extra = link.stats().request_telegrams - t_plan;
    REQUIRE(ops::execute_plan(c, *plan, ro).ok());
    auto v = ops::verify_restore(c, *plan, ro);
    REQUIRE(v.ok());
    const auto restore = link.stats().request_telegrams - extra;
    std::printf(
        "undo record of the demo restore onto %s: %llu telegrams besides the restore's "
        "%llu (%.1f%%)\n",
        name, static_cast<unsigned long long>(extra), static_cast<unsigned long long>(restore),
        100.0 * static_cast<double>(extra) / static_cast<double>(restore));
    CHECK(extra * 20 <= restore);  // at most 5 %
  }
}

TEST_CASE(
    "undo: the rotation keeps the newest 10 records of a drive, the listing is newest "
    "first, per drive",
    "[undo]") {
  test::ScratchDir dir("undo-rotation");
  test::SimRig rig("commissioned-axis.json");
  auto record = ops::undo_config_for_parameter(*rig.client, 0x13A2, db::Database::empty());
  REQUIRE(record.ok());
  ops::UndoOptions uo{true, dir.path, "sim:axis.json", 0x11, "set", ops::kUndoKeep};
  const auto t = std::chrono::system_clock::from_time_t(1795540500);  // 2026-11-24T17:15:00Z
  std::vector<fs::path> paths;
  for (int i = 0; i < 12; ++i) {
    // Two records in the same second: the second one is numbered.
    auto saved =
        ops::save_undo(uo, *record, db::Database::empty(), t + std::chrono::seconds(i / 2 * 60));
    REQUIRE(saved.ok());
    CHECK(saved->removed.size() == (i < 10 ? 0u : 1u));
    paths.push_back(saved->path);
  }
  const fs::path drive = dir.path / "sim_axis.json-11h";
  CHECK(paths[0] == drive / "20261124T171500Z-set.json");
  CHECK(paths[1] == drive / "20261124T171500Z.2-set.json");
  CHECK(paths[11] == drive / "20261124T172000Z.2-set.json");
  CHECK(files_in(dir.path) == 10);
  CHECK_FALSE(fs::exists(paths[0]));
  CHECK_FALSE(fs::exists(paths[1]));

  uo.port = "/dev/ttyUSB1";
  uo.command = "default";
  REQUIRE(ops::save_undo(uo, *record, db::Database::empty(), t).ok());

  auto all = ops::list_undo(dir.path);
  REQUIRE(all.ok());
  REQUIRE(all->size() == 11);
  CHECK((*all)[0].drive == "_dev_ttyUSB1-11h");
  CHECK((*all)[0].command == "default");
  CHECK((*all)[1].drive == "sim_axis.json-11h");
  CHECK((*all)[1].path == paths[11]);
  CHECK((*all)[1].time == "2026-11-24T17:20:00Z");
  CHECK((*all)[2].path == paths[10]);
  CHECK((*all)[10].path == paths[2]);
  const auto n = record->layer(2).size();
  CHECK((*all)[1].holds == "MC " + std::to_string(n) + " parameters");

  auto one = ops::list_undo(dir.path, "_dev_ttyUSB1-11h");
  REQUIRE(one.ok());
  CHECK(one->size() == 1);
  auto none = ops::list_undo(dir.path / "nowhere");
  REQUIRE(none.ok());
  CHECK(none->empty());
}

TEST_CASE(
    "undo: run_restore saves the record before its first write, none without undo, a "
    "record it cannot save refuses with nothing written",
    "[undo]") {
  const auto file = demo_backup();
  test::ScratchDir dir("undo-run");
  auto drive = test::load_sim_drive("used-spare.json");
  const auto before_state = drive->state();
  ops::RestoreRunOptions o;
  o.restore.include_comm = true;

  SECTION("without undo: no record") {
    auto session = sim_session(drive);
    auto out = ops::run_restore(*session, file, db::Database::empty(), o);
    CHECK(out.stage == ops::RestoreOutcome::Stage::restored);
    CHECK_FALSE(out.undo);
    CHECK(files_in(dir.path) == 0);
  }
  SECTION("with undo: the record, then the restore; the record restores the spare") {
    o.undo = ops::UndoOptions{true, dir.path, "sim:undo", drive->macid(), "restore", 10};
    auto session = sim_session(drive);
    auto out = ops::run_restore(*session, file, db::Database::empty(), o);
    REQUIRE(out.stage == ops::RestoreOutcome::Stage::restored);
    REQUIRE(out.undo);
    CHECK(files_in(dir.path) == 1);
    auto rec = config::read_config_file(out.undo->path);
    REQUIRE(rec.ok());
    o.undo.command = "undo";
    auto back = ops::run_restore(*session, *rec, db::Database::empty(), o);
    CHECK(back.stage == ops::RestoreOutcome::Stage::restored);
    CHECK(files_in(dir.path) == 2);
    CHECK(drive->state().curves_flash == before_state.curves_flash);
    CHECK(drive->state().ct_flash == before_state.ct_flash);
    std::map<std::uint16_t, std::uint32_t> now, then;
    for (const auto& [upid, p] : drive->state().params)
      if (p.modified()) now[upid] = p.rom;
    for (const auto& [upid, p] : before_state.params)
      if (p.modified()) then[upid] = p.rom;
    CHECK(now == then);
  }
  SECTION("a record that cannot be saved: refused, nothing written") {
    test::spit(dir.path / "undo", "a file where the directory should be");
    o.undo = ops::UndoOptions{true, dir.path / "undo", "sim:undo", drive->macid(), "restore", 10};
    auto session = sim_session(drive);
    auto out = ops::run_restore(*session, file, db::Database::empty(), o);
    CHECK(out.stage == ops::RestoreOutcome::Stage::failed);
    CHECK_FALSE(out.written);
    REQUIRE(out.error);
    CHECK(out.error->code == ErrorClass::bad_input);
    const std::string d = (dir.path / "undo" / "sim_undo-11h").string();
    CHECK(out.error->message == "cannot save the undo record: " + d +
                                    ": cannot create the directory: Not a directory; nothing "
                                    "written (--no-undo writes without it)");
    CHECK(drive->state().params == before_state.params);
    CHECK(drive->state().curves_ram == before_state.curves_ram);
  }
}

TEST_CASE("undo: default saves the layers it defaults and the tables it deletes", "[undo]") {
  test::ScratchDir dir("undo-default");
  test::SimRig rig("commissioned-axis.json");
  const auto before = read_back(*rig.client);
  ops::DefaultOptions d;
  d.layers = {false, true, false, true};
  d.curves = true;
  d.command_table = true;
  d.undo = ops::UndoOptions{true, dir.path, "/dev/ttyS0", 0x11, "default", 10};
  auto rep = ops::default_drive(*rig.client, d, db::Database::empty());
  REQUIRE(rep.ok());
  REQUIRE(rep->undo);
  CHECK(rep->undo->path.filename().string().ends_with("-default.json"));
  auto rec = config::read_config_file(rep->undo->path);
  REQUIRE(rec.ok());
  CHECK(rec->scope.layers == std::array<bool, 4>{false, true, false, true});
  CHECK(rec->scope.curves);
  CHECK(rec->scope.command_table);
  auto expected = before;
  expected.scope.layers = {false, true, false, true};
  CHECK(content_of(*rec) == content_of(expected));
  CHECK_FALSE(rec->curves.empty());
  CHECK_FALSE(rec->ct_entries.empty());

  // Restoring the record brings the defaulted layers and the tables back.
  ops::RestoreOptions ro;
  ro.include_comm = true;
  restore(*rig.client, *rec, ro);
  CHECK(content_of(read_back(*rig.client)) == content_of(before));
}

}  // namespace ops_test_undo

// README end to end, in process: backup a commissioned axis, restore onto a
// used spare, and prove the spare's ROM values, flash curves and flash command
// table equal the source's and the leftovers are gone; diff against defaults
// lists exactly the modified UPIDs; every bad input is refused with a precise
// message and zero write telegrams on the wire.
#include <unistd.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>

#include "db/compiler.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "ops/backup.hpp"
#include "ops/diff.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_e2e_restore {

using namespace lmcfg;

namespace {

config::DriveConfig backup_of(test::SimRig& rig, const db::Database& db) {
  auto cfg = ops::backup(*rig.client, ops::BackupOptions{}, db);
  REQUIRE(cfg.ok());
  return std::move(cfg).value();
}

// Modified ROM values per the simulated drive's own state.
std::map<std::uint16_t, std::uint32_t> modified_rom(const sim::Drive& d) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : d.state().params)
    if (p.modified()) m[upid] = p.rom;
  return m;
}

// The UPIDs a diff lists as differing parameters.
std::set<std::uint16_t> listed_upids(const ops::DiffResult& r) {
  std::set<std::uint16_t> listed;
  for (const auto& it : r.items)
    if (it.kind == ops::DiffItem::Kind::parameter)
      listed.insert(static_cast<std::uint16_t>(it.key));
  return listed;
}

std::set<std::uint16_t> modified_upids(const sim::Drive& d) {
  std::set<std::uint16_t> m;
  for (const auto& [upid, value] : modified_rom(d)) m.insert(upid);
  return m;
}

}  // namespace

TEST_CASE("e2e: backup, restore onto a used spare, spare equals source", "[e2e]") {
  auto db = test::built_database();
  const db::Database& dbp = db ? *db : db::Database::empty();
  test::SimRig source("commissioned-axis.json");
  test::SimRig spare("used-spare.json");
  const auto file = backup_of(source, dbp);
  REQUIRE_FALSE(file.curves.empty());
  REQUIRE_FALSE(file.ct_entries.empty());
  REQUIRE(modified_rom(*spare.drive) != modified_rom(*source.drive));

  ops::RestoreOptions ro;
  ro.include_comm = true;  // the two fixtures share line settings: restore everything
  auto plan = ops::plan_restore(*spare.client, file, dbp, ro);
  REQUIRE(plan.ok());
  for (auto& p : plan->problems) UNSCOPED_INFO(p);
  REQUIRE(plan->ok());
  auto exec = ops::execute_plan(*spare.client, *plan, ro);
  INFO((exec.ok() ? std::string() : exec.error().message));
  REQUIRE(exec.ok());
  auto verify = ops::verify_restore(*spare.client, *plan, ro);
  REQUIRE(verify.ok());
  for (auto& m : verify->mismatches) UNSCOPED_INFO(m);
  CHECK(verify->ok());

  // The spare's stored state, looked at from inside the simulated drive.
  CHECK(modified_rom(*spare.drive) == modified_rom(*source.drive));
  CHECK(spare.drive->state().curves_flash == source.drive->state().curves_flash);
  CHECK(spare.drive->state().ct_flash == source.drive->state().ct_flash);
  CHECK(spare.drive->state().mc_running);

  // And a second restore of the same file converges to the same state.
  auto again = ops::plan_restore(*spare.client, file, dbp, ro);
  REQUIRE(again.ok());
  REQUIRE(ops::execute_plan(*spare.client, *again, ro).ok());
  CHECK(modified_rom(*spare.drive) == modified_rom(*source.drive));
}

TEST_CASE("e2e: diff against defaults lists exactly the modified UPIDs", "[e2e]") {
  test::SimRig source("commissioned-axis.json");
  const auto file = backup_of(source, db::Database::empty());
  auto r = ops::diff(ops::factory_defaults_config(), file, db::Database::empty(), {},
                     ops::DiffOptions{true, false});
  CHECK(listed_upids(r) == modified_upids(*source.drive));
  // Curves and command table entries are listed too, each once.
  std::size_t curves = 0, entries = 0;
  for (const auto& it : r.items) {
    curves += it.kind == ops::DiffItem::Kind::curve;
    entries += it.kind == ops::DiffItem::Kind::ct_entry;
  }
  CHECK(curves == source.drive->state().curves_flash.size());
  CHECK(entries == source.drive->state().ct_flash.size());
}

TEST_CASE("e2e: a diff of two backups of one drive is empty", "[e2e]") {
  test::SimRig source("commissioned-axis.json");
  auto a = backup_of(source, db::Database::empty());
  auto b = backup_of(source, db::Database::empty());
  CHECK(ops::diff(a, b, db::Database::empty(), {}, ops::DiffOptions{true, false}).identical());
  // A changed command table entry is summarised by content.
  REQUIRE_FALSE(b.ct_entries.empty());
  b.ct_entries[0].raw[38] = 'X';
  auto r = ops::diff(a, b, db::Database::empty(), {}, ops::DiffOptions{true, false});
  REQUIRE(r.items.size() == 1);
  CHECK(r.items[0].kind == ops::DiffItem::Kind::ct_entry);
}

TEST_CASE("e2e: bad inputs refuse the restore with zero write telegrams on the wire", "[e2e]") {
  test::SimRig source("commissioned-axis.json");
  const auto good = backup_of(source, db::Database::empty());
  struct Case {
    const char* name;
    std::function<void(config::DriveConfig&)> spoil;
    const char* expected;  // a problem line must contain this
  };
  const std::vector<Case> cases{
      {"unknown UPID on the target",
       [](auto& c) {
         c.layer(2).push_back({0x1EEE, 1, std::nullopt, std::nullopt, {}, {}, {}});
       },
       "MC 1EEEh: UPID does not exist on the target (not in its MC UPID list, §10.3)"},
      {"read-only UPID (address usage from the target's UPID list)",
       [](auto& c) {
         c.layer(1).push_back({0x0E00, 1, std::nullopt, std::nullopt, {}, {}, {}});
       },
       "OS 0E00h: read-only on the target (the target's address usage 1001h has no ROM write bit)"},
      {"wrong type", [](auto& c) { c.layer(2).front().type = 0x06; },
       "type differs: the file has SINT32, the target has"},
      {"out-of-range value",
       [](auto& c) {
         for (auto& p : c.layer(2))
           if (p.upid == 0x13A2) p.value = 0x10000;
       },
       "MC 13A2h: value 10000h does not fit type UINT16"},
      {"oversize curve", [](auto& c) { c.curves.front().data.resize(70000); },
       "curve 1: a block exceeds the 16-bit size field of §11 (65535 bytes)"},
      {"command table entry of the wrong size",
       [](auto& c) { c.ct_entries.front().raw.resize(60); }, "bytes, expected 64"},
      {"curve ID outside 1..100", [](auto& c) { c.curves.front().id = 101; },
       "curve 101: ID outside 1..100"},
  };
  for (const auto& k : cases) {
    SECTION(k.name) {
      test::SimRig spare("used-spare.json");
      auto before = spare.drive->state();
      auto file = good;
      k.spoil(file);
      auto plan =
          ops::plan_restore(*spare.client, file, db::Database::empty(), ops::RestoreOptions{});
      REQUIRE(plan.ok());
      REQUIRE_FALSE(plan->ok());
      bool found = false;
      for (const auto& p : plan->problems) found |= p.find(k.expected) != std::string::npos;
      for (const auto& p : plan->problems) UNSCOPED_INFO(p);
      CHECK(found);
      auto exec = ops::execute_plan(*spare.client, *plan, ops::RestoreOptions{});
      REQUIRE_FALSE(exec.ok());
      CHECK(exec.error().code == Errc::plan_refused);
      CHECK(spare.wire->write_telegrams() == 0);
      CHECK(spare.drive->state().params == before.params);
    }
  }
}

TEST_CASE("e2e: offline diff against defaults uses the defaults a capture recorded", "[e2e]") {
  test::SimRig source("commissioned-axis.json");
  // A full capture lists every ROM-writable UPID, most of them at their
  // default: without the recorded defaults each would look like a difference.
  ops::BackupOptions bo;
  bo.full = true;
  auto full = ops::backup(*source.client, bo, db::Database::empty());
  REQUIRE(full.ok());
  auto r = ops::diff(ops::factory_defaults_config(), *full, db::Database::empty(), {},
                     ops::DiffOptions{true, false});
  CHECK(listed_upids(r) == modified_upids(*source.drive));
  // Values are shown by their recorded type: 11F2h is SINT16 on the drive.
  bool shown = false;
  for (const auto& it : r.items) {
    if (it.key != 0x11F2) continue;
    CHECK(it.a == "default 0");
    CHECK(it.b ==
          std::to_string(static_cast<std::int16_t>(source.drive->state().params.at(0x11F2).rom)));
    shown = true;
  }
  CHECK(shown);
  REQUIRE_FALSE(r.notes.empty());
  CHECK(r.notes.back().find(
            "default value(s) the UPID database does not know were taken from the capture") !=
        std::string::npos);
}

TEST_CASE(
    "e2e: with address usage from the database the plan asks types, an unknown UPID answers C8h",
    "[e2e]") {
  // A database that knows the address usage of every MC UPID of the file.
  auto dir =
      std::filesystem::temp_directory_path() / ("lmcfg-e2e-au-" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "profiles.tsv") << "profile\tfamily\tsoftware\tversion\tdescription\tsource\n"
                                         "p\tE1100\tMC\t\t\ttest\n";
  std::ofstream(dir / "parameters.tsv")
      << "upid\tprofiles\tlayer\tname\tpath\ttype\taddress_"
         "usage\tmin\tmax\tdefault\tunit\tscale\tenum\tcomm\t"
         "description\tsource\n"
         "13A2\tp\tMC\tP Gain\t\tUINT16\t000F\t\t\t\t\t\t\t\t\ttest\n"
         "1EEE\tp\tMC\tNot On This Drive\t\tUINT16\t000F\t\t\t\t\t\t\t\t\ttest\n";
  const auto out = (dir / "au.sqlite").string();
  auto rep = db::compile_upid_db(dir.string(), out);
  REQUIRE(rep.ok());
  auto database = db::Database::open(out);
  REQUIRE(database.ok());

  test::SimRig spare("used-spare.json");
  config::DriveConfig file;
  file.scope.layers = {false, true, false, false};
  file.scope.curves = file.scope.command_table = false;
  file.layer(2) = {{0x13A2, 40, std::nullopt, std::nullopt, {}, {}, {}},
                   {0x1EEE, 1, std::nullopt, std::nullopt, {}, {}, {}}};
  auto plan = ops::plan_restore(*spare.client, file, *database, ops::RestoreOptions{});
  REQUIRE(plan.ok());
  REQUIRE(plan->problems.size() == 1);
  CHECK(plan->problems[0] ==
        "MC 1EEEh Not On This Drive: UPID does not exist on the target (type query answered C8h "
        "unknown UPID)");
  // No UPID list was walked: the only list read is the modified list.
  for (const auto& n : plan->notes) CHECK(n.find("UPID list") == std::string::npos);
  CHECK(spare.wire->write_telegrams() == 0);
  std::filesystem::remove_all(dir);
}

}  // namespace tools_test_e2e_restore

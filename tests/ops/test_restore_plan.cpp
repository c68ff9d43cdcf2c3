// The restore plan (lib/ops/restore_plan.cpp) against simulated drives, in
// process: values a target of another firmware cannot take (refused by
// default, skipped with skip_incompatible), flash saves only for the tables
// whose entries are written, the second pass after a reset that reloaded a
// table from a flash holding another one, and a drive that refuses
// configuration writes while MC runs.
#include <algorithm>
#include <catch2/catch.hpp>

#include "client/client.hpp"
#include "db/database.hpp"
#include "e2e_support.hpp"
#include "ops/backup.hpp"
#include "ops/restore.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_plan {

using namespace lmcfg;

namespace {

using Action = ops::PlanStep::Action;

struct Rig {
  std::shared_ptr<sim::Drive> drive;
  sim::SimLink link;
  client::LinrsClient client;
  explicit Rig(sim::DriveState s)
      : drive(std::make_shared<sim::Drive>(std::move(s))),
        link(drive),
        client(link, client::ClientOptions{}) {}
};

sim::DriveState fixture(const char* name) {
  auto s = sim::load_state(test::sim_fixture(name));
  REQUIRE(s.ok());
  return std::move(s).value();
}

config::DriveConfig backup_of(const sim::DriveState& st) {
  Rig rig(st);
  auto cfg = ops::backup(rig.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(cfg.ok());
  return std::move(cfg).value();
}

// A used spare with another firmware than the commissioned axis: it lacks
// 1037h, has 13A6h as UINT32 (the file: UINT16), allows 1022h only from 50
// (the file: 47) and has no ROM write bit on 3010h.
sim::DriveState other_firmware() {
  auto s = fixture("used-spare.json");
  s.params.erase(0x1037);
  s.params.at(0x13A6).type = type_code(TypeCode::UInt32);
  s.params.at(0x1022).min = 50;
  s.params.at(0x3010).address_usage = sim::au::ram_read | sim::au::ram_write | sim::au::rom_read;
  return s;
}

std::size_t count(const ops::Plan& p, Action a) {
  return static_cast<std::size_t>(std::count_if(
      p.steps.begin(), p.steps.end(), [&](const ops::PlanStep& s) { return s.action == a; }));
}

// Modified ROM values per the simulated drive's own state.
std::map<std::uint16_t, std::uint32_t> modified(const sim::DriveState& s) {
  std::map<std::uint16_t, std::uint32_t> m;
  for (const auto& [upid, p] : s.params)
    if (p.modified()) m[upid] = p.rom;
  return m;
}

const std::vector<std::string> kIncompatible = {
    "MC 1022h: value 47 is below the minimum 50 (as the target reports it, §10 05h 05h/06h)",
    "MC 1037h: UPID does not exist on the target (not in its MC UPID list, §10.3)",
    "MC 13A6h: type differs: the file has UINT16, the target has UINT32",
    "Appl 3010h: read-only on the target (the target's address usage 0007h has no ROM write "
    "bit)",
};

}  // namespace

TEST_CASE("restore plan: values another firmware cannot take refuse the restore by default",
          "[restore][skip-incompatible]") {
  const auto file = backup_of(fixture("commissioned-axis.json"));
  Rig rig(other_firmware());
  ops::RestoreOptions ro;
  ro.include_comm = true;  // the fixtures' LinRS parameters select the same line
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  CHECK(plan->problems == kIncompatible);
  CHECK(plan->skipped_incompatible.empty());
  CHECK(plan->steps.empty());
  CHECK(rig.client.stats().write_requests == 0);
  CHECK_FALSE(ops::execute_plan(rig.client, *plan, ro).ok());
}

TEST_CASE(
    "restore plan: skip_incompatible writes the rest, lists each value with its reason, "
    "verifies, and a second run has nothing to do",
    "[restore][skip-incompatible]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  Rig rig(other_firmware());
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.skip_incompatible = true;
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  std::vector<std::string> texts;
  std::vector<std::string> codes;
  for (const auto& v : plan->skipped_incompatible) {
    texts.push_back(v.text);
    codes.push_back(ops::reason_code(v.reason));
    CHECK(v.kind == ops::SkippedValue::Kind::parameter);
  }
  CHECK(texts == kIncompatible);
  CHECK(codes == std::vector<std::string>{"out_of_range", "upid_absent", "type_differs",
                                          "not_rom_writable"});
  CHECK(plan->skipped_incompatible[1].key == 0x1037);
  CHECK(plan->skipped_incompatible[1].layer == 2);
  CHECK(plan->skipped_incompatible[1].why ==
        "UPID does not exist on the target (not in its MC UPID list, §10.3)");
  // Not written, not expected.
  for (const auto& s : plan->steps)
    if (s.action == Action::write_rom) {
      INFO(s.text);
      CHECK(s.key != 0x1022);
      CHECK(s.key != 0x13A6);
      CHECK(s.key != 0x3010);
    }
  CHECK(plan->expected.find_param(0x1022) == nullptr);
  CHECK(plan->expected.find_param(0x1037) == nullptr);
  const auto rendered = ops::render_plan(*plan);
  CHECK(rendered.find("skipped (the target cannot take them):\n"
                      "  MC 1022h: value 47 is below the minimum 50 (as the target reports it, "
                      "§10 05h 05h/06h)\n"
                      "  MC 1037h: UPID does not exist") != std::string::npos);
  const auto j = ops::plan_json(*plan);
  REQUIRE(j["skipped_incompatible"].size() == 4);
  const auto& absent = j["skipped_incompatible"][1];
  CHECK(absent["layer"] == "MC");
  CHECK(absent["upid"] == "1037");
  CHECK(absent["name"] == "");
  CHECK(absent["reason_code"] == "upid_absent");
  CHECK(absent["reason"] == "UPID does not exist on the target (not in its MC UPID list, §10.3)");
  CHECK(absent.size() == 5);

  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  for (const auto& m : v->mismatches) UNSCOPED_INFO(m);
  CHECK(v->ok());
  // The rest equals the source; the values the target could not take are at
  // the target's default (the used spare's own 1022h/13A6h/3010h were not
  // modified), 1037h does not exist.
  auto want = modified(source);
  want.erase(0x1022);
  want.erase(0x1037);
  want.erase(0x13A6);
  want.erase(0x3010);
  CHECK(modified(rig.drive->state()) == want);
  CHECK(rig.drive->state().ct_flash == source.ct_flash);
  CHECK(rig.drive->state().curves_flash == source.curves_flash);

  auto again = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(again.ok());
  CHECK(again->nothing_to_do());
  CHECK(again->skipped_incompatible.size() == 4);
  CHECK(ops::render_plan(*again).rfind(
            "plan: nothing to do: the target already matches the file except the skipped values "
            "(no write, MC keeps running)\n",
            0) == 0);
}

TEST_CASE("restore plan: a skipped value modified on the target goes back to its default",
          "[restore][skip-incompatible]") {
  const auto file = backup_of(fixture("commissioned-axis.json"));
  auto target = other_firmware();
  target.params.at(0x1022).rom = 60;  // modified, inside the target's range
  Rig rig(target);
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.skip_incompatible = true;
  ro.default_first = false;
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  const auto it = std::find_if(plan->steps.begin(), plan->steps.end(),
                               [](const ops::PlanStep& s) { return s.key == 0x1022; });
  REQUIRE(it != plan->steps.end());
  CHECK(it->text == "write ROM MC 1022h: 60 (003Ch) -> 100 (0064h) (leftover back to its default)");
  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  CHECK(v->ok());
  CHECK(rig.drive->rom(0x1022) == 100u);
}

TEST_CASE("restore plan: curve and command table limits are incompatible values",
          "[restore][skip-incompatible]") {
  const auto source = fixture("commissioned-axis.json");
  auto file = backup_of(source);
  REQUIRE(file.curves.size() == 2);
  REQUIRE(file.ct_entries.size() == 5);
  config::Curve extra = file.curves[0];
  extra.id = 101;
  file.curves.push_back(extra);
  file.ct_entries[1].raw.pop_back();  // entry 2: 63 bytes
  ops::RestoreOptions ro;
  ro.include_comm = true;
  // Room for curve 1 only: curve 2 is left out (the highest ID first).
  ro.curve_memory = file.curves[0].info.size() + file.curves[0].data.size();
  const std::size_t memory =
      ro.curve_memory + file.curves[1].info.size() + file.curves[1].data.size();
  {
    Rig rig(source);
    auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
    REQUIRE(plan.ok());
    CHECK(plan->problems ==
          std::vector<std::string>{"curve 101: ID outside 1..100",
                                   "curves need " + std::to_string(memory) +
                                       " bytes of curve memory; the drive has " +
                                       std::to_string(ro.curve_memory),
                                   "command table entry 2: 63 bytes, expected 64"});
  }
  ro.skip_incompatible = true;
  Rig rig(source);
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  std::vector<std::string> got;
  for (const auto& v : plan->skipped_incompatible)
    got.push_back(std::string(ops::reason_code(v.reason)) + " " + std::to_string(v.key) + ": " +
                  v.why);
  CHECK(got == std::vector<std::string>{
                   "curve_id_limit 101: ID outside 1..100",
                   "curve_memory 2: the file's curves need " + std::to_string(memory) +
                       " bytes of curve memory, the drive has " + std::to_string(ro.curve_memory) +
                       "; left out from the highest ID down until the rest fits",
                   "ct_entry_size 2: 63 bytes, expected 64"});
  const auto j = ops::plan_json(*plan);
  CHECK(j["skipped_incompatible"][0]["curve"] == 101);
  CHECK(j["skipped_incompatible"][2]["ct_entry"] == 2);
  CHECK(j["skipped_incompatible"][2]["reason_code"] == "ct_entry_size");
  // As if the file did not hold them: the target's curve 2 and entry 2 go.
  REQUIRE(plan->losses.size() == 2);
  CHECK(plan->losses[0] == "command table entry 2 '" +
                               config::ct_entry_name(source.ct_flash.at(2)) +
                               "' deleted (not in the file)");
  CHECK(plan->losses[1].rfind("curve 2 '", 0) == 0);
  CHECK(plan->losses[1].find("' deleted (not in the file)") != std::string::npos);
  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  CHECK(v->ok());
  CHECK(rig.drive->state().curves_flash.size() == 1);
  CHECK(rig.drive->state().ct_flash.count(2) == 0);
}

// ---- flash saves only for tables whose entries are written ------------------

TEST_CASE(
    "restore plan: one gain and one curve changed save the curves to flash, not the command "
    "table",
    "[restore][flash]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  auto target = source;
  target.params.at(0x13A2).rom = target.params.at(0x13A2).ram = 55;
  target.curves_flash.at(1).data.at(0) ^= 0x01;
  target.curves_ram = target.curves_flash;
  Rig rig(target);
  ops::RestoreOptions ro;
  ro.include_comm = true;
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  CHECK(count(*plan, Action::write_rom) == 1);
  CHECK(count(*plan, Action::write_curve) == 1);
  CHECK(count(*plan, Action::save_curves) == 1);
  CHECK(count(*plan, Action::write_ct) == 0);
  CHECK(count(*plan, Action::save_ct) == 0);
  CHECK(count(*plan, Action::reset) == 1);
  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  CHECK(rig.drive->stats().flash_saves == 1);
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  CHECK(v->ok());
  CHECK(rig.drive->state().curves_flash == source.curves_flash);
}

TEST_CASE(
    "restore: a command table whose flash differs from RAM is written and saved in a second "
    "pass after the reset",
    "[restore][flash]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  auto target = source;
  target.params.at(0x13A2).rom = target.params.at(0x13A2).ram = 55;
  target.ct_ram = source.ct_flash;  // RAM matches the file, flash holds another table
  target.ct_flash.erase(6);
  target.ct_flash.at(5).at(0) ^= 0x01;
  Rig rig(target);
  ops::RestoreOptions ro;
  ro.include_comm = true;
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  CHECK(count(*plan, Action::save_ct) == 0);
  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  CHECK(v->mismatches == std::vector<std::string>{"command table: drive defines 4 entries, the "
                                                  "file 5",
                                                  "command table entry 5: bytes differ"});
  CHECK(v->ct_differs);
  CHECK_FALSE(v->curves_differ);
  auto pass = ops::plan_table_pass(rig.client, *plan, *v, ro);
  REQUIRE(pass.ok());
  std::vector<Action> actions;
  for (const auto& s : pass->steps) actions.push_back(s.action);
  CHECK(actions == std::vector<Action>{Action::stop_mc, Action::delete_ct, Action::write_ct,
                                       Action::write_ct, Action::save_ct, Action::start_mc});
  REQUIRE(ops::execute_plan(rig.client, *pass, ro).ok());
  auto again = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(again.ok());
  CHECK(again->ok());
  CHECK(rig.drive->state().ct_flash == source.ct_flash);
  // A table the first pass saved gets no second pass.
  auto saved = *plan;
  ops::PlanStep s;
  s.action = Action::save_ct;
  saved.steps.push_back(s);
  auto none = ops::plan_table_pass(rig.client, saved, *v, ro);
  REQUIRE(none.ok());
  CHECK(none->steps.empty());
}

// ---- a drive that refuses configuration writes while MC runs ----------------

TEST_CASE(
    "restore: the plan stops MC first, so a drive that refuses configuration writes while MC "
    "runs takes them, without the stop it refuses (LinRS §10)",
    "[restore][mc-stopped]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  auto target = fixture("used-spare.json");
  target.options.refuse_config_while_mc_runs = true;
  ops::RestoreOptions ro;
  ro.include_comm = true;
  {
    Rig rig(target);
    auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
    REQUIRE(plan.ok());
    REQUIRE(plan->ok());
    REQUIRE_FALSE(plan->steps.empty());
    CHECK(plan->steps.front().action == Action::stop_mc);
    REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
    auto v = ops::verify_restore(rig.client, *plan, ro);
    REQUIRE(v.ok());
    CHECK(v->ok());
    CHECK(modified(rig.drive->state()) == modified(source));
  }
  Rig rig(target);
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  auto without_stop = *plan;
  without_stop.steps.erase(without_stop.steps.begin());
  auto r = ops::execute_plan(rig.client, without_stop, ro);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == ErrorClass::drive_refusal);  // exit 5 (README "Exit codes")
  CHECK(r.error().message.rfind("restore stopped at step 1 of " +
                                    std::to_string(without_stop.steps.size()) + " (" +
                                    without_stop.steps.front().text + "): ",
                                0) == 0);
  CHECK(modified(rig.drive->state()) == modified(target));
}

TEST_CASE(
    "LinRS 3V27 p32 restore plan onto a C1100: curves and command table written on flash, no save",
    "[restore][flash][families]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  auto target = source;
  target.options.family = "C1100";  // the simulator keeps curves and CT on flash
  target.curves_flash.at(1).data.at(0) ^= 0x01;
  target.curves_ram = target.curves_flash;
  target.ct_flash.begin()->second.at(6) ^= 0x01;
  target.ct_ram = target.ct_flash;
  Rig rig(target);
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.family = families::find("C1100");
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  CHECK(count(*plan, Action::write_curve) == 1);
  CHECK(count(*plan, Action::write_ct) == 1);
  CHECK(count(*plan, Action::save_curves) == 0);
  CHECK(count(*plan, Action::save_ct) == 0);
  REQUIRE(ops::execute_plan(rig.client, *plan, ro).ok());
  CHECK(rig.drive->stats().flash_saves == 0);
  auto v = ops::verify_restore(rig.client, *plan, ro);
  REQUIRE(v.ok());
  CHECK(v->ok());
  CHECK(rig.drive->state().curves_flash == source.curves_flash);
  CHECK(rig.drive->state().ct_flash == source.ct_flash);
}

TEST_CASE("LinRS 3V27 §11-§12 restore plan onto a B1100: a file's curves and CT are refused",
          "[restore][families]") {
  const auto source = fixture("commissioned-axis.json");
  const auto file = backup_of(source);
  auto target = source;
  target.options.family = "B1100";
  Rig rig(target);
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.family = families::find("B1100");
  auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  CHECK(plan->problems ==
        std::vector<std::string>{
            "the file has a curve in scope, but a B1100 has no curve group (LinRS 3V27 §11); "
            "--skip-incompatible restores the rest",
            "the file has a command table in scope, but a B1100 has no command table group "
            "(LinRS 3V27 §12); --skip-incompatible restores the rest"});
  CHECK(plan->steps.empty());
  CHECK(rig.client.stats().write_requests == 0);
  ro.skip_incompatible = true;
  auto skipped = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
  REQUIRE(skipped.ok());
  CHECK(skipped->ok());
  CHECK(count(*skipped, Action::write_curve) == 0);
  CHECK(count(*skipped, Action::save_ct) == 0);
  CHECK(std::count(skipped->skipped.begin(), skipped->skipped.end(),
                   "the file's curve: a B1100 has no curve group (LinRS 3V27 §11)") == 1);
  CHECK_FALSE(skipped->expected.scope.curves);
}

TEST_CASE(
    "LinRS §16.1 restore plan onto a drive that answers C3h for the table groups, family not "
    "named: a file without tables plans nothing there, a file with tables is refused or skipped",
    "[restore][families]") {
  auto b1100 = fixture("commissioned-axis.json");
  b1100.options.family = "B1100";  // C3h undefined main ID on groups 04h and 08h
  // Its own backup (no curves, no command table: drive_lacks) goes back with
  // nothing to write at all.
  const auto own = backup_of(b1100);
  REQUIRE(own.scope.drive_lacks == std::vector<std::string>{"curves", "command_table"});
  {
    Rig rig(b1100);
    auto plan = ops::plan_restore(rig.client, own, db::Database::empty(), ops::RestoreOptions{});
    REQUIRE(plan.ok());
    CHECK(plan->ok());
    CHECK(plan->steps.empty());
    CHECK_FALSE(plan->expected.scope.curves);
    CHECK(rig.client.stats().write_requests == 0);
  }
  // An E1100's file in scope with empty tables: nothing to write there, said.
  auto empty = backup_of(fixture("commissioned-axis.json"));
  empty.curves.clear();
  empty.ct_entries.clear();
  {
    Rig rig(b1100);
    auto plan = ops::plan_restore(rig.client, empty, db::Database::empty(), ops::RestoreOptions{});
    REQUIRE(plan.ok());
    CHECK(plan->ok());
    CHECK(count(*plan, Action::save_curves) == 0);
    CHECK(count(*plan, Action::save_ct) == 0);
    CHECK(std::count(plan->notes.begin(), plan->notes.end(),
                     "the target has no curve group (it answers C3h undefined message main ID, "
                     "LinRS §16.1); the file holds no curves: nothing to write there") == 1);
    CHECK(plan->expected.scope.drive_lacks == std::vector<std::string>{"command_table", "curves"});
  }
  // A file that holds curves and entries: refused, said; skipped on request.
  const auto full = backup_of(fixture("commissioned-axis.json"));
  REQUIRE_FALSE(full.curves.empty());
  REQUIRE_FALSE(full.ct_entries.empty());
  Rig rig(b1100);
  auto plan = ops::plan_restore(rig.client, full, db::Database::empty(), ops::RestoreOptions{});
  REQUIRE(plan.ok());
  CHECK(plan->problems ==
        std::vector<std::string>{
            "the file holds " + std::to_string(full.ct_entries.size()) +
                " command table entries, but the target has no command table group (it answers "
                "C3h undefined message main ID, LinRS §16.1); --skip-incompatible restores the "
                "rest",
            "the file holds " + std::to_string(full.curves.size()) +
                " curve(s), but the target has no curve group (it answers C3h undefined message "
                "main ID, LinRS §16.1); --skip-incompatible restores the rest"});
  CHECK(plan->steps.empty());
  CHECK(rig.client.stats().write_requests == 0);
  ops::RestoreOptions skip;
  skip.skip_incompatible = true;
  auto skipped = ops::plan_restore(rig.client, full, db::Database::empty(), skip);
  REQUIRE(skipped.ok());
  CHECK(skipped->ok());
  CHECK(count(*skipped, Action::write_curve) == 0);
  CHECK(count(*skipped, Action::write_ct) == 0);
  CHECK(std::count(skipped->skipped.begin(), skipped->skipped.end(),
                   "the file's " + std::to_string(full.curves.size()) +
                       " curve(s): the target has no curve group (it answers C3h undefined "
                       "message main ID, LinRS §16.1)") == 1);
  CHECK_FALSE(skipped->expected.scope.curves);
  CHECK_FALSE(skipped->expected.scope.command_table);
}

TEST_CASE(
    "LinRS 3V27 p27 restore plan: a target that answers 05h/03h is asked each address usage, "
    "one that does not has its UPID list walked",
    "[restore][families]") {
  // The database is empty: no address usage known, so the target must tell.
  const auto file = backup_of(fixture("commissioned-axis.json"));
  for (const bool answers : {true, false}) {
    INFO("address usage request answered: " << answers);
    auto target = other_firmware();
    target.options.address_usage_request = answers;
    Rig rig(target);
    ops::RestoreOptions ro;
    ro.include_comm = true;
    auto plan = ops::plan_restore(rig.client, file, db::Database::empty(), ro);
    REQUIRE(plan.ok());
    const auto asked = std::count_if(plan->notes.begin(), plan->notes.end(), [](auto& n) {
      return n.find("asked the target for each (05h/03h, LinRS 3V27 p27)") != std::string::npos;
    });
    const auto walked = std::count_if(plan->notes.begin(), plan->notes.end(), [](auto& n) {
      return n.find("read the target's UPID list") != std::string::npos;
    });
    CHECK((answers ? asked : walked) > 0);
    CHECK((answers ? walked : asked) == 0);
    // Either way the same values are found incompatible; only the absent UPID's
    // reason names how it was found.
    REQUIRE(plan->problems.size() == 4);
    CHECK(plan->problems[3] ==
          "Appl 3010h: read-only on the target (the target's address usage 0007h has no ROM "
          "write bit)");
    CHECK(plan->problems[1] ==
          (answers ? "MC 1037h: UPID does not exist on the target (type query answered C8h "
                     "unknown UPID)"
                   : "MC 1037h: UPID does not exist on the target (not in its MC UPID list, "
                     "§10.3)"));
  }
}

}  // namespace ops_test_restore_plan

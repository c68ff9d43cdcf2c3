// `lmcfg restore` as one library call (lib/ops/restore_run.cpp) against the
// in-process simulated drive: every outcome stage (plan refused, dry run,
// declined, nothing to do, restored, verify mismatch, failed), what is
// written before each of them, the confirmation's place, an interruption
// while planning, and the second pass after a reset that reloaded a table.
#include <atomic>
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "e2e_support.hpp"
#include "link/session.hpp"
#include "ops/backup.hpp"
#include "ops/restore_run.hpp"
#include "session_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_run {

using namespace lmcfg;
using Stage = ops::RestoreOutcome::Stage;

namespace {

using test::demo_backup;
using RunRig = test::SessionRig;

// Restores every parameter, the LinRS ones too: the fixtures' LinRS
// parameters select the line they are served on (docs/simulator.md).
ops::RestoreRunOptions everything() {
  ops::RestoreRunOptions o;
  o.restore.include_comm = true;
  return o;
}

}  // namespace

TEST_CASE("restore run: the stage names and the outcome names with skipped values",
          "[restore_run]") {
  CHECK(std::string(ops::stage_name(Stage::failed)) == "failed");
  CHECK(std::string(ops::stage_name(Stage::plan_refused)) == "plan refused");
  CHECK(std::string(ops::stage_name(Stage::dry_run)) == "dry run");
  CHECK(std::string(ops::stage_name(Stage::declined)) == "declined");
  CHECK(std::string(ops::stage_name(Stage::nothing_to_do)) == "nothing to do");
  CHECK(std::string(ops::stage_name(Stage::verify_mismatch)) == "verify mismatch");
  CHECK(std::string(ops::stage_name(Stage::restored)) == "restored and verified");

  ops::RestoreOutcome out;
  out.stage = Stage::restored;
  CHECK_FALSE(out.skipped_any());
  CHECK(ops::outcome_name(out) == "restored and verified");
  out.plan.skipped_incompatible.emplace_back();
  CHECK(out.skipped_any());
  CHECK(ops::outcome_name(out) == "restored except the listed values, verified");
  out.stage = Stage::nothing_to_do;
  CHECK(ops::outcome_name(out) == "nothing to do except the listed values");
  // Other stages keep their names whether or not values were skipped.
  out.stage = Stage::verify_mismatch;
  CHECK(ops::outcome_name(out) == "verify mismatch");
  out.stage = Stage::failed;
  CHECK(ops::outcome_name(out) == "failed");
}

TEST_CASE("restore run: onto a used spare, confirmed once, written and verified", "[restore_run]") {
  const auto file = demo_backup();
  RunRig rig(test::load_sim_drive("used-spare.json"));
  auto o = everything();
  int asked = 0;
  o.confirm = [&](const ops::Plan& p) -> Result<ops::Consent> {
    ++asked;
    CHECK_FALSE(p.steps.empty());
    CHECK(rig.wire->write_telegrams() == 0);  // asked before any write
    return ops::Consent::go;
  };
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
  INFO((out.error ? out.error->message : std::string()));
  CHECK(out.stage == Stage::restored);
  CHECK(ops::outcome_name(out) == "restored and verified");
  CHECK(asked == 1);
  CHECK(out.written);
  CHECK_FALSE(out.error);
  CHECK(out.mismatches.empty());
  CHECK_FALSE(out.second_pass);
  CHECK_FALSE(out.undo);  // undo not enabled
  // The file's LinRS settings differ from the spare's (--include-comm): after
  // the reset the drive was looked for and found again.
  CHECK(out.plan.link_may_change);
  CHECK(out.relink);
  CHECK_FALSE(out.devicenet);
  CHECK(rig.wire->write_telegrams() == out.plan.write_telegrams);
  CHECK(rig.drive->state().mc_running);

  // The same file again: the plan's reads are the verification, nothing written.
  const auto writes = rig.wire->write_telegrams();
  asked = 0;
  const auto again = ops::run_restore(*rig.session, file, db::Database::empty(), o);
  CHECK(again.stage == Stage::nothing_to_do);
  CHECK(ops::outcome_name(again) == "nothing to do");
  CHECK_FALSE(again.written);
  CHECK(asked == 0);
  CHECK(rig.wire->write_telegrams() == writes);
  CHECK(rig.drive->state().mc_running);
}

TEST_CASE("restore run: a dry run, a declined plan and a failed confirmation write nothing",
          "[restore_run]") {
  const auto file = demo_backup();
  auto drive = test::load_sim_drive("used-spare.json");
  const auto before = drive->state();
  int asked = 0;
  SECTION("dry run: the plan, no confirmation") {
    RunRig rig(drive);
    auto o = everything();
    o.dry_run = true;
    o.confirm = [&](const ops::Plan&) -> Result<ops::Consent> {
      ++asked;
      return ops::Consent::go;
    };
    const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
    CHECK(out.stage == Stage::dry_run);
    CHECK(ops::outcome_name(out) == "dry run");
    CHECK_FALSE(out.plan.steps.empty());
    CHECK(asked == 0);
    CHECK_FALSE(out.written);
    CHECK(rig.wire->write_telegrams() == 0);
  }
  SECTION("declined") {
    RunRig rig(drive);
    auto o = everything();
    o.confirm = [&](const ops::Plan&) -> Result<ops::Consent> {
      ++asked;
      return ops::Consent::declined;
    };
    const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
    CHECK(out.stage == Stage::declined);
    CHECK(asked == 1);
    CHECK_FALSE(out.written);
    CHECK_FALSE(out.error);
    CHECK(rig.wire->write_telegrams() == 0);
  }
  SECTION("the confirmation fails: its error, as it is") {
    RunRig rig(drive);
    auto o = everything();
    o.confirm = [&](const ops::Plan&) -> Result<ops::Consent> {
      return Error(Errc::invalid_argument,
                   "standard input is not a terminal: give --yes to restore without asking");
    };
    const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
    CHECK(out.stage == Stage::failed);
    REQUIRE(out.error);
    CHECK(out.error->code == Errc::invalid_argument);
    CHECK(out.error->message ==
          "standard input is not a terminal: give --yes to restore without asking");
    CHECK_FALSE(out.written);
    CHECK(rig.wire->write_telegrams() == 0);
  }
  CHECK(drive->state().params == before.params);
  CHECK(drive->state().ct_ram == before.ct_ram);
  CHECK(drive->state().curves_ram == before.curves_ram);
  CHECK(drive->state().mc_running);
}

TEST_CASE(
    "LinRS §12.1 restore run: a command table entry size the target does not have refuses "
    "the plan",
    "[restore_run]") {
  const auto file = demo_backup();
  REQUIRE_FALSE(file.ct_entries.empty());
  RunRig rig(test::load_sim_drive("used-spare.json"));
  auto o = everything();
  o.restore.ct_entry_size = 32;  // §12.1 entries are 64 bytes; this target takes 32
  bool asked = false;
  o.confirm = [&](const ops::Plan&) -> Result<ops::Consent> {
    asked = true;
    return ops::Consent::go;
  };
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
  CHECK(out.stage == Stage::plan_refused);
  CHECK(ops::outcome_name(out) == "plan refused");
  CHECK_FALSE(out.plan.ok());
  CHECK(out.plan.problems.size() == file.ct_entries.size());
  CHECK_FALSE(asked);
  CHECK_FALSE(out.written);
  CHECK_FALSE(out.error);
  CHECK(rig.wire->write_telegrams() == 0);
}

TEST_CASE("restore run: interrupted while planning, nothing written", "[restore_run][interrupt]") {
  const auto file = demo_backup();
  std::atomic<bool> flag{true};
  RunRig rig(test::load_sim_drive("used-spare.json"), "sim:run", &flag);
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), everything());
  CHECK(out.stage == Stage::failed);
  REQUIRE(out.error);
  CHECK(out.error->code == Errc::interrupted);
  CHECK(out.error->message ==
        "interrupted while planning (reads only): interrupted by a signal before the next "
        "telegram; nothing written");
  CHECK_FALSE(out.written);
  CHECK(rig.wire->tx.empty());
}

TEST_CASE("restore run: a value that changes behind the restore is a verify mismatch",
          "[restore_run]") {
  const auto file = demo_backup();
  const auto* gain = file.find_param(0x13A2);
  REQUIRE(gain != nullptr);
  auto drive = test::load_sim_drive("used-spare.json");
  RunRig rig(drive);
  // When the reset arrives (after every ROM write), 13A2h's ROM value is changed
  // on the drive: what verify reads back differs from the file.
  const auto cfg = drive->state().checksum;
  rig.sim->faults().set_callback([&, cfg](std::size_t, ByteView req) -> std::vector<sim::Fault> {
    auto t = codec::decode(req, cfg);
    if (t.ok() && t->main == 0x06 && t->sub == 0x01) {
      auto& p = drive->state().params.at(0x13A2);
      p.rom = p.ram = gain->value + 1;
    }
    return {};
  });
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), everything());
  INFO((out.error ? out.error->message : std::string()));
  CHECK(out.stage == Stage::verify_mismatch);
  CHECK(ops::outcome_name(out) == "verify mismatch");
  CHECK(out.written);
  REQUIRE(out.mismatches.size() == 1);
  CHECK(out.mismatches[0].find("13A2h") != std::string::npos);
}

TEST_CASE(
    "restore run: a command table the reset reloaded from another flash gets one second "
    "pass, then verifies",
    "[restore_run]") {
  auto source = test::load_sim_drive("commissioned-axis.json")->state();
  const auto file = demo_backup();
  auto target = source;
  target.params.at(0x13A2).rom = target.params.at(0x13A2).ram = 55;
  target.ct_ram = source.ct_flash;  // RAM matches the file, flash holds another table
  target.ct_flash.erase(6);
  auto drive = std::make_shared<sim::Drive>(target);
  RunRig rig(drive);
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), everything());
  INFO((out.error ? out.error->message : std::string()));
  CHECK(out.stage == Stage::restored);
  REQUIRE(out.second_pass);
  CHECK_FALSE(out.second_pass->steps.empty());
  CHECK(out.mismatches.empty());
  CHECK(drive->state().ct_flash == source.ct_flash);
  CHECK(drive->state().mc_running);
}

TEST_CASE("restore run: the error each way a restore ends with", "[restore_run]") {
  using S = ops::RestoreOutcome::Stage;
  ops::RestoreOutcome out;
  for (S s : {S::dry_run, S::declined, S::nothing_to_do, S::restored}) {
    out.stage = s;
    CHECK_FALSE(ops::outcome_error(out).has_value());
  }
  out.stage = S::failed;
  out.error = Error(Errc::timeout, "no answer to step 3");
  CHECK(ops::outcome_error(out)->message == "no answer to step 3");
  out.stage = S::plan_refused;
  out.plan.problems = {"2012h: 9 is above the target's max 8", "no curve 4"};
  const auto refused = ops::outcome_error(out);
  CHECK(refused->code == make_error_code(Errc::plan_refused));
  CHECK(refused->message ==
        "restore refused: 2012h: 9 is above the target's max 8; no curve 4; nothing written");
  out.stage = S::verify_mismatch;
  out.mismatches = {"13A2h: 7 != 5"};
  const auto differs = ops::outcome_error(out);
  CHECK(differs->code == make_error_code(Errc::verify_mismatch));
  CHECK(differs->message == "written, but the drive reads back differently: 13A2h: 7 != 5");
}

}  // namespace ops_test_restore_run

// One restore path for LinRS and LinUDP: ops::run_restore (plan, execute,
// verify) over a LinUDP session to the simulated drive (virtual clock), under
// the field behaviours of the C1250 notes and field reports and both readings
// of the points LinUDP V2 leaves open; and a restore cut in the middle.
#include <catch2/catch.hpp>

#include "db/database.hpp"
#include "linudp_rig.hpp"
#include "ops/restore_run.hpp"
#include "session_rig.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_linudp_restore {

using namespace lmcfg;
using Stage = ops::RestoreOutcome::Stage;

namespace {

constexpr std::int64_t kSeconds = 1'000'000;

struct Reading {
  const char* name;
  sim::LinudpField field;
  std::int64_t save_s = 0;
};

std::vector<Reading> readings() {
  std::vector<Reading> r;
  r.push_back({"the manual's reading", {}, 0});
  sim::LinudpField f;
  f.unacknowledged_saves = true;
  r.push_back({"field reports: unacknowledged 39 s saves", f, 39});
  r.push_back({"C1250 notes: unacknowledged 75 s saves", f, 75});
  f = {};
  r.push_back({"C1250 notes: acknowledged 75 s saves", f, 75});
  f = {};
  f.silent_after_rom_write_us = 30 * kSeconds;
  r.push_back({"C1250 notes: silent 30 s after ROM writes", f, 0});
  f = {};
  f.stale_echo_every = 2;
  r.push_back({"C1250 notes: stale echoes", f, 0});
  f = {};
  f.lose_reply_every = 7;
  r.push_back({"lost replies", f, 0});
  f = {};
  f.lose_save_requests = 2;  // both saves (CT, curves): LinUDP V2 §7, C1250 notes
  r.push_back({"lost save requests", f, 39});
  f = {};
  f.lose_save_replies = 2;
  r.push_back({"lost save replies", f, 39});
  f = {};
  f.lose_save_requests = 2;
  f.unacknowledged_saves = true;
  r.push_back({"lost save requests, saves never acknowledged", f, 39});
  f = {};
  f.lose_save_requests = 2;
  f.running_status = 0;
  r.push_back({"lost save requests, silent while saving", f, 39});
  f = {};
  f.end_on_extra_read = true;
  r.push_back({"open in LinUDP V2: 00h on one more read", f, 0});
  f = {};
  f.list_spans_layers = true;
  r.push_back({"open in LinUDP V2: lists span the layers", f, 0});
  f = {};
  f.curve_start_gives_sizes = false;
  r.push_back({"open in LinUDP V2: 60h without sizes", f, 0});
  f = {};
  f.strict_counts = true;
  r.push_back({"open in LinUDP V2: counts 1 and 15 refused", f, 0});
  f = {};
  f.running_status = 0x05;
  r.push_back({"open in LinUDP V2: 05h while running", f, 5});
  f = {};
  f.running_status = 0;
  r.push_back({"open in LinUDP V2: silent while running", f, 5});
  return r;
}

}  // namespace

TEST_CASE("LinUDP restore: plan, execute and verify onto a used spare under each reading",
          "[linudp][restore_run]") {
  const auto file = test::demo_backup();
  for (const auto& rd : readings()) {
    DYNAMIC_SECTION(rd.name) {
      auto drive = test::load_sim_drive("used-spare.json");
      auto field = rd.field;
      field.save_us = rd.save_s * kSeconds;
      test::LinudpRig rig(drive, field);
      ops::RestoreRunOptions o;
      const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
      INFO((out.error ? out.error->message : std::string()));
      std::string problems;
      for (const auto& pr : out.plan.problems) problems += pr + "\n";
      for (const auto& m : out.mismatches) problems += m + "\n";
      INFO(problems);
      REQUIRE(out.stage == Stage::restored);
      CHECK(out.mismatches.empty());
      CHECK_FALSE(out.plan.link_may_change);
      CHECK(rig.udp->stats().motion_telegrams == 0);
      CHECK(drive->state().mc_running);
      CHECK(drive->state().ct_flash == drive->state().ct_ram);
      CHECK(drive->state().curves_flash == drive->state().curves_ram);
      if (rd.field.unacknowledged_saves) CHECK_FALSE(out.unacknowledged.empty());
      // Each save carried out once: none lost for good, none twice (C1250 notes).
      CHECK(rig.udp->stats().saves == 2);
      // The same file again: nothing to do.
      const auto again = ops::run_restore(*rig.session, file, db::Database::empty(), o);
      CHECK(again.stage == Stage::nothing_to_do);
    }
  }
}

TEST_CASE("LinUDP restore: the drive holds what a LinRS restore of the same file leaves",
          "[linudp][restore_run]") {
  const auto file = test::demo_backup();
  auto over_udp = test::load_sim_drive("used-spare.json");
  test::LinudpRig udp(over_udp);
  REQUIRE(ops::run_restore(*udp.session, file, db::Database::empty(), {}).stage == Stage::restored);
  auto over_rs = test::load_sim_drive("used-spare.json");
  test::SessionRig rs(over_rs);
  REQUIRE(ops::run_restore(*rs.session, file, db::Database::empty(), {}).stage == Stage::restored);
  for (const auto& [upid, p] : over_rs->state().params) {
    INFO("UPID " << upid);
    CHECK(over_udp->state().params.at(upid).rom == p.rom);
  }
  CHECK(over_udp->state().curves_flash == over_rs->state().curves_flash);
  CHECK(over_udp->state().ct_flash == over_rs->state().ct_flash);
}

TEST_CASE("LinUDP restore cut in the middle: the drive stops answering after the first writes",
          "[linudp][restore_run]") {
  const auto file = test::demo_backup();
  auto drive = test::load_sim_drive("used-spare.json");
  test::LinudpRig rig(drive);
  ops::RestoreRunOptions o;
  o.restore.progress = [&](const std::string& phase, std::size_t n, std::size_t) {
    if (phase == "restore" && n == 4) rig.udp->field().lose_request_every = 1;  // cable pulled
  };
  auto opt = rig.client().options();
  opt.recover_timeout = client::Millis(20000);
  rig.client().set_options(opt);
  const auto out = ops::run_restore(*rig.session, file, db::Database::empty(), o);
  REQUIRE(out.stage == Stage::failed);
  CHECK(out.written);
  REQUIRE(out.error);
  CHECK(out.error->code == ErrorClass::link_failure);
  INFO(out.error->message);
  CHECK(out.error->message.find("LinUDP drive at linudp-sim") != std::string::npos);
}

}  // namespace ops_test_linudp_restore

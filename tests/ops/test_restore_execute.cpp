// Executing a restore plan (lib/ops/restore_execute.cpp) against the
// in-process simulated drive: steps in order as the manual's telegrams, the
// recovery record written before the first step and deleted after the last,
// the messages naming the step where a restore stops or is interrupted, and
// the lost answer to a reset that changes the link.
#include <atomic>
#include <catch2/catch.hpp>
#include <filesystem>

#include "codec/frame.hpp"
#include "files.hpp"
#include "ops/recovery.hpp"
#include "ops/restore.hpp"
#include "test_reliability_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_restore_execute {

using namespace lmcfg;
using Action = ops::PlanStep::Action;
using test::FaultRig;
namespace fs = std::filesystem;

namespace {

ops::PlanStep step(Action a, std::string text) {
  ops::PlanStep s;
  s.action = a;
  s.text = std::move(text);
  return s;
}

ops::PlanStep write(int layer, std::uint16_t upid, std::uint32_t value, ops::WriteReason why) {
  ops::PlanStep s = step(Action::write_rom, "write " + hex(upid, 4, "h"));
  s.layer = layer;
  s.key = upid;
  s.value = value;
  s.reason = why;
  return s;
}

// stop MC, two ROM writes (one a kept communication value), reset.
ops::Plan small_plan() {
  ops::Plan p;
  p.steps = {step(Action::stop_mc, "stop MC"), write(2, 0x13A2, 40, ops::WriteReason::differs),
             write(3, 0x2076, 0x11, ops::WriteReason::kept_communication),
             step(Action::reset, "reset")};
  return p;
}

std::shared_ptr<sim::Drive> demo_drive() { return test::load_sim_drive("commissioned-axis.json"); }

std::vector<std::string> sent_hex(const test::WireRecorder& w) {
  std::vector<std::string> out;
  for (const auto& t : w.tx) out.push_back(to_hex(t));
  return out;
}

}  // namespace

TEST_CASE("restore execute: a plan with problems writes nothing", "[restore_execute]") {
  FaultRig rig(demo_drive());
  ops::Plan p = small_plan();
  p.problems = {"MC 1037h: UPID does not exist on the target"};
  auto r = ops::execute_plan(*rig.client, p, ops::RestoreOptions{});
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::plan_refused);
  CHECK(r.error().message == "the plan has problems; nothing written");
  CHECK(rig.wire->tx.empty());
}

// LinRS §13.3 "Tx: 01 11 03 02 03 06 04" (stop MC), §13.4 "Tx: 01 11 03 02 04 06 04"
// (start MC with response after completion).
TEST_CASE("LinRS §13.3 §13.4 restore execute: the steps in order, MC stopped and started",
          "[restore_execute]") {
  auto drive = demo_drive();
  FaultRig rig(drive);
  ops::Plan p;
  p.steps = {step(Action::stop_mc, "stop MC"), write(2, 0x13A2, 40, ops::WriteReason::differs),
             step(Action::start_mc, "start MC")};
  std::vector<std::string> progress;
  ops::RestoreOptions ro;
  ro.progress = [&](const std::string& phase, std::size_t done, std::size_t total) {
    progress.push_back(phase + " " + std::to_string(done) + "/" + std::to_string(total));
  };
  auto r = ops::execute_plan(*rig.client, p, ro);
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  CHECK(progress == std::vector<std::string>{"restore 1/3", "restore 2/3", "restore 3/3"});
  const auto sent = sent_hex(*rig.wire);
  REQUIRE(sent.size() >= 3);
  CHECK(sent.front() == "01 11 03 02 03 06 04");
  CHECK(sent.back() == "01 11 03 02 04 06 04");
  CHECK(rig.wire->write_telegrams() == 3);
  CHECK(drive->rom(0x13A2) == std::optional<std::uint32_t>(40));
  CHECK(drive->state().mc_running);
}

TEST_CASE(
    "restore execute: the recovery record exists from before the first step to after the "
    "last and holds the kept communication values",
    "[restore_execute]") {
  test::ScratchDir dir("execute-record");
  auto drive = demo_drive();
  FaultRig rig(drive);
  ops::RestoreOptions ro;
  ro.recovery_path = dir.path / "restore-sim_test-11h.json";
  ro.port = "sim:test";
  std::vector<bool> seen;
  std::optional<ops::RecoveryRecord> at_first;
  ro.progress = [&](const std::string&, std::size_t done, std::size_t) {
    seen.push_back(fs::exists(ro.recovery_path));
    if (done == 1) {
      auto rec = ops::load_recovery(ro.recovery_path);
      REQUIRE(rec.ok());
      at_first = *rec;
      CHECK(rig.wire->tx.empty());  // written before the first telegram
    }
  };
  const auto p = small_plan();
  REQUIRE(ops::execute_plan(*rig.client, p, ro).ok());
  CHECK(seen == std::vector<bool>{true, true, true, true});
  REQUIRE(at_first);
  CHECK(at_first->command == "restore");
  CHECK(at_first->port == "sim:test");
  CHECK(at_first->macid == 0x11);
  CHECK(at_first->expect.empty());
  REQUIRE(at_first->keep.size() == 1);  // only the kept communication value
  CHECK(at_first->keep[0].upid == 0x2076);
  CHECK(at_first->keep[0].value == 0x11);
  CHECK_FALSE(fs::exists(ro.recovery_path));

  // No path: no record anywhere, nothing to delete.
  FaultRig again(drive, {}, rig.now_ns() + 10'000'000'000);
  REQUIRE(ops::execute_plan(*again.client, p, ops::RestoreOptions{}).ok());
}

TEST_CASE(
    "restore execute: a record that cannot be written stops the restore before its first "
    "telegram",
    "[restore_execute]") {
  test::ScratchDir dir("execute-no-record");
  test::spit(dir.path / "blocker", "");
  FaultRig rig(demo_drive());
  ops::RestoreOptions ro;
  ro.recovery_path = dir.path / "blocker" / "restore.json";
  auto r = ops::execute_plan(*rig.client, small_plan(), ro);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::file_error);
  CHECK(r.error().message.rfind(
            (dir.path / "blocker").string() + ": cannot create the recovery directory: ", 0) == 0);
  CHECK(rig.wire->tx.empty());
}

TEST_CASE(
    "restore execute: a link lost at a write names the step, says MC is stopped and keeps "
    "the record",
    "[restore_execute]") {
  test::ScratchDir dir("execute-lost");
  auto drive = demo_drive();
  FaultRig rig(drive);
  test::aim(rig, test::request(0x05, 0x01), 1, sim::Fault::close_link());
  ops::RestoreOptions ro;
  ro.recovery_path = dir.path / "restore.json";
  auto r = ops::execute_plan(*rig.client, small_plan(), ro);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::link_closed);
  const std::string& m = r.error().message;
  CHECK(m.rfind("restore stopped at step 2 of 4 (write 13A2h): ", 0) == 0);
  const std::string tail =
      ". The drive is partially configured and MC is stopped: run the same restore again to "
      "converge.";
  REQUIRE(m.size() > tail.size());
  CHECK(m.substr(m.size() - tail.size()) == tail);
  CHECK(m.find("telegram in flight") == std::string::npos);
  CHECK(fs::exists(ro.recovery_path));
  CHECK_FALSE(drive->state().mc_running);
}

TEST_CASE("restore execute: an interruption names the step and the completed telegram",
          "[restore_execute][interrupt]") {
  auto drive = demo_drive();
  std::atomic<bool> flag{false};
  client::ClientOptions co;
  co.cancel = &flag;
  FaultRig rig(drive, co);
  ops::RestoreOptions ro;
  // The signal arrives while step 2 is under way, before its telegram.
  ro.progress = [&](const std::string&, std::size_t done, std::size_t) {
    if (done == 2) flag = true;
  };
  auto r = ops::execute_plan(*rig.client, small_plan(), ro);
  REQUIRE_FALSE(r.ok());
  CHECK(r.error().code == Errc::interrupted);
  CHECK(r.error().message ==
        "restore interrupted at step 2 of 4 (write 13A2h): interrupted by a signal before the "
        "next telegram (the telegram in flight was completed). The drive is partially "
        "configured and MC is stopped: run the same restore again to converge.");
  CHECK(rig.wire->tx.size() == 1);  // the stop MC only

  // Before MC was stopped (or after it was started again) the message does not say it is.
  flag = true;
  ops::Plan only_write;
  only_write.steps = {write(2, 0x13A2, 40, ops::WriteReason::differs)};
  auto w = ops::execute_plan(*rig.client, only_write, ops::RestoreOptions{});
  REQUIRE_FALSE(w.ok());
  CHECK(w.error().message ==
        "restore interrupted at step 1 of 1 (write 13A2h): interrupted by a signal before the "
        "next telegram (the telegram in flight was completed). The drive is partially "
        "configured: run the same restore again to converge.");
}

TEST_CASE(
    "LinRS §13.1 restore execute: a reset's lost answer is accepted only when the link may "
    "change",
    "[restore_execute]") {
  ops::Plan p;
  p.steps = {step(Action::stop_mc, "stop MC"), step(Action::reset, "reset")};
  {
    // Without polling (recover_timeout 0) a lost answer stops the restore.
    client::ClientOptions o;
    o.recover_timeout = client::Millis(0);
    FaultRig rig(demo_drive(), o);
    test::aim(rig, test::request(0x06, 0x01), 1, sim::Fault::drop_answer());
    auto r = ops::execute_plan(*rig.client, p, ops::RestoreOptions{});
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().code == Errc::timeout);
    CHECK(r.error().message.rfind("restore stopped at step 2 of 2 (reset): ", 0) == 0);
  }
  {
    // With it (the default, docs/field.md "Slow saves"): the drive is found
    // again and the step is listed as unacknowledged for the verify to decide.
    FaultRig rig(demo_drive());
    test::aim(rig, test::request(0x06, 0x01), 1, sim::Fault::drop_answer());
    std::vector<std::string> unacked;
    auto r = ops::execute_plan(*rig.client, p, ops::RestoreOptions{}, &unacked);
    INFO((r.ok() ? std::string() : r.error().message));
    REQUIRE(r.ok());
    CHECK(unacked == std::vector<std::string>{
                         "step 2 (reset): the drive did not acknowledge resetting the drive within "
                         "120 s and answered again 0 s later"});
  }
  {
    p.link_may_change = true;
    FaultRig rig(demo_drive());
    auto aimed = test::aim(rig, test::request(0x06, 0x01), 1, sim::Fault::drop_answer());
    auto r = ops::execute_plan(*rig.client, p, ops::RestoreOptions{});
    INFO((r.ok() ? std::string() : r.error().message));
    CHECK(r.ok());
    CHECK(aimed.hit->has_value());
  }
}

TEST_CASE("restore execute: a whole plan onto a used spare leaves it equal to the file",
          "[restore_execute]") {
  FaultRig source(demo_drive());
  auto file = ops::backup(*source.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(file.ok());
  auto spare = test::load_sim_drive("used-spare.json");
  FaultRig rig(spare);
  ops::RestoreOptions ro;
  ro.include_comm = true;  // the fixtures' LinRS parameters select the same line
  auto plan = ops::plan_restore(*rig.client, *file, db::Database::empty(), ro);
  REQUIRE(plan.ok());
  REQUIRE(plan->ok());
  const auto before = rig.wire->write_telegrams();
  CHECK(before == 0);
  auto r = ops::execute_plan(*rig.client, *plan, ro);
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  CHECK(test::drive_vs_file(*spare, *file).empty());
  CHECK(spare->state().mc_running);
  // The plan's estimate counts the write telegrams the steps sent.
  CHECK(rig.wire->write_telegrams() == plan->write_telegrams);
}

}  // namespace ops_test_restore_execute

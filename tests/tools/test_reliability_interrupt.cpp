// docs/reliability.md: a small restore (a few parameters, one small curve, two command
// table entries) onto a used spare, interrupted at EVERY telegram index in turn
// (the link closes at exchange k). The interrupted run must report failure;
// the same restore run again on a fresh link to the same drive must end with
// the drive equal to the file: ROM values of the file's UPIDs, the modified
// list, flash curves and flash command table.
#include <atomic>
#include <catch2/catch.hpp>
#include <filesystem>

#include "db/database.hpp"
#include "ops/factory_reset.hpp"
#include "test_reliability_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace tools_test_reliability_interrupt {

using namespace lmcfg;
using test::FaultRig;

namespace {

config::DriveConfig small_file() {
  FaultRig src(test::load_sim_drive("commissioned-axis.json"));
  auto b = ops::backup(*src.client, ops::BackupOptions{}, db::Database::empty());
  REQUIRE(b.ok());
  config::DriveConfig f = std::move(b).value();
  // Keep two layers with a few parameters each, the smallest curve, two CT entries.
  int kept_layers = 0;
  for (int layer = 1; layer <= 4; ++layer) {
    auto& l = f.layer(layer);
    if (l.empty() || kept_layers == 2) {
      f.scope.layers[static_cast<std::size_t>(layer - 1)] = false;
      l.clear();
      continue;
    }
    ++kept_layers;
    if (l.size() > 3) l.resize(3);
  }
  REQUIRE(kept_layers > 0);
  REQUIRE_FALSE(f.curves.empty());
  std::sort(f.curves.begin(), f.curves.end(), [](const auto& x, const auto& y) {
    return x.info.size() + x.data.size() < y.info.size() + y.data.size();
  });
  f.curves.resize(1);
  REQUIRE(f.ct_entries.size() >= 2);
  f.ct_entries.resize(2);
  config::canonicalize(f);
  return f;
}

}  // namespace

TEST_CASE("restore interrupted at every telegram: reported as failed, a rerun converges",
          "[reliability][interrupt]") {
  const auto file = small_file();
  const auto spare = test::load_sim_drive("used-spare.json")->state();
  ops::RestoreOptions ro;
  ro.include_comm = true;  // the fixtures' LinRS parameters select the same line
  ro.max_curve_id = 8;     // the file's curve lies below; keeps every run short
  ro.recovery_path = test::restore_record();

  // A clean run: how many exchanges a whole restore (plan, write, verify) takes.
  std::size_t total = 0;
  {
    auto drive = std::make_shared<sim::Drive>(spare);
    test::forget_restore_record();
    FaultRig rig(drive);
    auto run = test::run_restore(*rig.client, file, ro);
    INFO((run.ok() ? std::string() : run.outcome.error().message));
    REQUIRE(run.ok());
    REQUIRE(test::drive_vs_file(*drive, file).empty());
    total = rig.sim->stats().write_calls;
    REQUIRE(rig.wire->write_telegrams() > 20);
  }
  REQUIRE(total > 50);

  std::size_t interrupted = 0, converged = 0, during_writes = 0;
  for (std::size_t k = 0; k < total; ++k) {
    auto drive = std::make_shared<sim::Drive>(spare);
    test::forget_restore_record();
    std::int64_t t_end = 0;
    std::size_t writes_before = 0;
    {
      FaultRig rig(drive);
      rig.sim->faults().schedule(k, sim::Fault::close_link());
      auto run = test::run_restore(*rig.client, file, ro);
      INFO("interrupted at exchange " << k << " of " << total);
      REQUIRE_FALSE(run.ok());  // never success
      CHECK(run.outcome.error().code == Errc::link_closed);
      if (run.outcome.error().code != Errc::link_closed) FAIL(run.outcome.error().message);
      ++interrupted;
      t_end = rig.now_ns();
      writes_before = rig.wire->write_telegrams();
    }
    if (writes_before > 0) ++during_writes;
    // The same restore on a fresh link to the same drive, a while later.
    FaultRig again(drive, {}, t_end + 10'000'000'000);
    auto second = test::run_restore(*again.client, file, ro);
    INFO("rerun after an interruption at exchange " << k << " of " << total);
    INFO((second.ok() ? std::string() : second.outcome.error().message));
    REQUIRE(second.ok());
    const auto diffs = test::drive_vs_file(*drive, file);
    for (const auto& d : diffs) UNSCOPED_INFO(d);
    REQUIRE(diffs.empty());
    CHECK(drive->state().mc_running);
    ++converged;
  }
  CHECK(interrupted == total);
  CHECK(converged == total);
  CHECK(during_writes > 0);
  std::printf(
      "interruption test: %zu interruption points (every telegram of a %zu-telegram restore), "
      "%zu after writes began, %zu reruns converged\n",
      interrupted, total, during_writes, converged);
}

namespace {

// Sets `flag` when the master sends its nth write request (1-based): the
// client must complete that telegram and send nothing after it.
void interrupt_at_write(FaultRig& rig, std::size_t nth, std::atomic<bool>& flag) {
  auto count = std::make_shared<std::size_t>(0);
  const auto cfg = rig.drive->state().checksum;
  rig.sim->faults().set_callback([=, &flag](std::size_t, ByteView req) -> std::vector<sim::Fault> {
    auto t = codec::decode(req, cfg);
    if (t.ok() && codec::is_write_request(*t) && ++*count == nth) flag = true;
    return {};
  });
}

}  // namespace

TEST_CASE(
    "SIGINT during the write phase (ClientOptions::cancel): the step is named, a rerun "
    "converges",
    "[reliability][interrupt][restore]") {
  const auto file = small_file();
  const auto spare = test::load_sim_drive("used-spare.json")->state();
  ops::RestoreOptions ro;
  ro.include_comm = true;
  ro.max_curve_id = 8;
  ro.recovery_path = test::restore_record();
  std::size_t tried = 0;
  for (std::size_t nth : {1u, 2u, 5u, 10u, 20u, 40u}) {
    INFO("interrupted at write request " << nth);
    auto drive = std::make_shared<sim::Drive>(spare);
    test::forget_restore_record();
    std::atomic<bool> flag{false};
    client::ClientOptions co;
    co.cancel = &flag;
    std::int64_t t_end = 0;
    {
      FaultRig rig(drive, co);
      interrupt_at_write(rig, nth, flag);
      auto run = test::run_restore(*rig.client, file, ro);
      if (!flag) continue;  // the restore had fewer writes
      ++tried;
      REQUIRE_FALSE(run.ok());
      CHECK(run.outcome.error().code == Errc::interrupted);
      const std::string& m = run.outcome.error().message;
      CHECK(m.rfind("restore interrupted at step ", 0) == 0);
      CHECK(m.find("(the telegram in flight was completed)") != std::string::npos);
      CHECK(m.find("run the same restore again to converge.") != std::string::npos);
      CHECK(std::filesystem::exists(test::restore_record()));
      t_end = rig.now_ns();
    }
    FaultRig again(drive, {}, t_end + 10'000'000'000);
    auto second = test::run_restore(*again.client, file, ro);
    INFO((second.ok() ? std::string() : second.outcome.error().message));
    REQUIRE(second.ok());
    CHECK(test::drive_vs_file(*drive, file).empty());
    CHECK(drive->state().mc_running);
    CHECK_FALSE(std::filesystem::exists(test::restore_record()));
  }
  CHECK(tried >= 4);
}

TEST_CASE(
    "default --layers intf: the first keep-write lost, the rerun restores the drive's own "
    "communication settings from the recovery record",
    "[reliability][interrupt][default]") {
  auto drive =
      std::make_shared<sim::Drive>(test::load_sim_drive("commissioned-axis.json")->state());
  const auto before = drive->state();
  REQUIRE(before.params.at(0x200E).rom == 2);  // baud rate "By Parameter"
  REQUIRE(before.params.at(0x206C).rom == 3);  // MACID "By Parameter"
  const auto record = std::filesystem::temp_directory_path() /
                      ("lmcfg-test-default-record-" + std::to_string(::getpid()) + ".json");
  std::filesystem::remove(record);
  ops::DefaultOptions opt;
  opt.layers = {false, false, true, false};
  opt.recovery_path = record;
  opt.port = "sim:test";
  std::int64_t t_end = 0;
  {
    FaultRig rig(drive);
    // The link closes at the first ROM write: the layer is defaulted, nothing kept yet.
    test::aim(rig, test::request(0x05, 0x01), 1, sim::Fault::close_link());
    auto r = ops::default_drive(*rig.client, opt, db::Database::empty());
    REQUIRE_FALSE(r.ok());
    CHECK(r.error().message.find("run the same command again; it finishes from the recovery "
                                 "record " +
                                 record.string()) != std::string::npos);
    CHECK(drive->state().params.at(0x200E).rom == before.params.at(0x200E).def);
    CHECK(std::filesystem::exists(record));
    t_end = rig.now_ns();
  }
  FaultRig again(drive, {}, t_end + 10'000'000'000);
  auto r = ops::default_drive(*again.client, opt, db::Database::empty());
  INFO((r.ok() ? std::string() : r.error().message));
  REQUIRE(r.ok());
  CHECK(r->recovered);
  CHECK(drive->state().params.at(0x200E).rom == 2);
  CHECK(drive->state().params.at(0x206C).rom == 3);
  CHECK_FALSE(std::filesystem::exists(record));
}

}  // namespace tools_test_reliability_interrupt

// Issue 7 §2: a small restore (a few parameters, one small curve, two command
// table entries) onto a used spare, interrupted at EVERY telegram index in turn
// (the link closes at exchange k). The interrupted run must report failure;
// the same restore run again on a fresh link to the same drive must end with
// the drive equal to the file: ROM values of the file's UPIDs, the modified
// list, flash curves and flash command table.
#include <catch2/catch.hpp>

#include "test_reliability_support.hpp"

using namespace lmcfg;
using test::FaultRig;

namespace {

config::DriveConfig small_file() {
  FaultRig src(test::load_sim_drive("commissioned-axis.json"));
  auto b = ops::backup(*src.client, ops::BackupOptions{}, nullptr);
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

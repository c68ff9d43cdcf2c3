// docs/reliability.md: soak. 1,000 backup/restore cycles against simulated drives with
// random faults (seeded, deterministic) and random configurations. Every run
// that reports success must have verified (the drive equals the file / the
// backup equals the drive, checked against the simulator's own state); every
// run that fails must have said so. Zero silent failures. A failed restore is
// run again without faults and must converge.
// LMCFG_SEED=N draws the cycles from seed N instead of 20261122;
// LMCFG_SOAK_CYCLES=N runs N cycles (the sanitizer build: scripts/test.sh).
// Twice: with CRC-CCITT (one read decides) and without a checksum, the
// factory setting, where the client's automatic agreeing reads must keep
// flipped value bits out (docs/reliability.md).
#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdlib>
#include <random>
#include <string>

#include "db/database.hpp"
#include "test_reliability_support.hpp"

// This file's own namespace: the test binary is a unity build (tests/CMakeLists.txt).
namespace ops_test_reliability_soak {

using namespace lmcfg;
using test::FaultRig;

namespace {

sim::Fault random_fault(std::mt19937& rng) {
  switch (std::uniform_int_distribution<int>(0, 11)(rng)) {
    case 0:
      return sim::Fault::corrupt(static_cast<std::size_t>(-1),
                                 static_cast<std::uint8_t>(1u << (rng() % 8)));
    case 1:
      return sim::Fault::corrupt(rng() % 16, 0xFF);
    case 2:
      return sim::Fault::drop_answer();
    case 3:
      return sim::Fault::drop_request();
    case 4:
      return sim::Fault::delay(std::uniform_int_distribution<std::uint32_t>(1, 190)(rng));
    case 5:
      return sim::Fault::delay(std::uniform_int_distribution<std::uint32_t>(201, 650)(rng));
    case 6:
      return sim::Fault::wrong_id();
    case 7:
      return sim::Fault::garbage_burst(Bytes(1 + rng() % 12, static_cast<std::uint8_t>(rng())));
    case 8:
      return sim::Fault::reset_drive(true);
    case 9:
      return sim::Fault::reset_drive(false);
    case 10:
      return sim::Fault::slow_flash();
    default:
      return sim::Fault::close_link();
  }
}

// A random configuration drawn from the commissioned axis's: a random subset
// of parameters, curves and command table entries (each may be empty).
config::DriveConfig random_config(const config::DriveConfig& all, std::mt19937& rng) {
  config::DriveConfig c = all;
  auto keep = [&](auto& v, int percent) {
    std::remove_reference_t<decltype(v)> kept;
    for (auto& x : v)
      if (static_cast<int>(rng() % 100) < percent) kept.push_back(x);
    v = kept;
  };
  const int p = 20 + static_cast<int>(rng() % 80);
  for (auto& l : c.layers) keep(l, p);
  keep(c.curves, 50);
  keep(c.ct_entries, 50);
  config::canonicalize(c);
  return c;
}

}  // namespace

TEST_CASE("soak: 1000 backup/restore cycles with random faults, zero silent failures",
          "[reliability][soak]") {
  const bool crc = GENERATE(true, false);
  const auto t0 = std::chrono::steady_clock::now();
  auto source = test::load_sim_drive("commissioned-axis.json")->state();
  auto spare = test::load_sim_drive("used-spare.json")->state();
  // With CRC corrupted bytes are detectable and one read decides; without,
  // the tools' automatic mode reads until 2 (3 on a corrupting line) agree.
  source.checksum.mode = spare.checksum.mode =
      crc ? codec::ChecksumMode::crc_ccitt : codec::ChecksumMode::none;
  client::ClientOptions copt;
  copt.agreeing_reads = crc ? 1 : 0;
  config::DriveConfig all;
  {
    FaultRig rig(std::make_shared<sim::Drive>(source), copt);
    auto b = ops::backup(*rig.client, ops::BackupOptions{}, db::Database::empty());
    REQUIRE(b.ok());
    all = std::move(b).value();
  }
  std::uint32_t seed = 20261122u;
  if (const char* seed_env = std::getenv("LMCFG_SEED"))
    seed = static_cast<std::uint32_t>(std::stoul(seed_env));
  std::mt19937 rng(seed);
  int cycles = 1000;
  if (const char* n = std::getenv("LMCFG_SOAK_CYCLES")) cycles = std::max(1, std::atoi(n));
  std::size_t faults = 0, restore_ok = 0, restore_failed = 0, backup_ok = 0, backup_failed = 0,
              silent = 0, reruns_converged = 0, telegrams = 0;
  ops::RestoreOptions ro;
  ro.include_comm = true;  // the fixtures' LinRS parameters select the same line
  ro.max_curve_id = 8;     // the commissioned axis's curves lie below; the probe stays short
  ro.recovery_path = test::restore_record();
  ops::BackupOptions bo;
  bo.max_curve_id = 8;
  for (int cycle = 0; cycle < cycles; ++cycle) {
    INFO("cycle " << cycle);
    const auto file = random_config(all, rng);
    auto drive = std::make_shared<sim::Drive>(spare);
    // Fault rate per exchange: none, light or heavy for this cycle.
    const double rate = std::array<double, 3>{0.0, 0.01, 0.05}[rng() % 3];
    auto fault_rng = std::make_shared<std::mt19937>(static_cast<std::uint32_t>(rng()));
    auto install = [&](FaultRig& rig) {
      rig.sim->faults().set_callback([=](std::size_t, ByteView) -> std::vector<sim::Fault> {
        if (std::uniform_real_distribution<double>(0, 1)(*fault_rng) >= rate) return {};
        return {random_fault(*fault_rng)};
      });
    };
    std::int64_t t_end = 0;
    test::forget_restore_record();  // a new drive
    {
      FaultRig rig(drive, copt);
      install(rig);
      auto run = test::run_restore(*rig.client, file, ro);
      faults += rig.sim->faults().counters().total();
      telegrams += rig.sim->stats().write_calls;
      const auto diffs = test::drive_vs_file(*drive, file);
      if (run.ok()) {
        ++restore_ok;
        if (!diffs.empty()) {
          ++silent;
          UNSCOPED_INFO("cycle " << cycle
                                 << ": restore reported success, drive differs: " << diffs.front());
        }
      } else {
        ++restore_failed;
        REQUIRE_FALSE(run.outcome.error().message.empty());
      }
      t_end = rig.now_ns();
    }
    if (restore_failed + restore_ok > 0 && !test::drive_vs_file(*drive, file).empty()) {
      // The failed restore, run again on a quiet fresh link, converges.
      FaultRig again(drive, copt, t_end + 10'000'000'000);
      auto second = test::run_restore(*again.client, file, ro);
      telegrams += again.sim->stats().write_calls;
      INFO((second.ok() ? std::string() : second.outcome.error().message));
      REQUIRE(second.ok());
      REQUIRE(test::drive_vs_file(*drive, file).empty());
      ++reruns_converged;
      t_end = again.now_ns();
    }
    // Backup of the restored drive under faults.
    {
      FaultRig rig(drive, copt, t_end + 10'000'000'000);
      install(rig);
      auto b = ops::backup(*rig.client, bo, db::Database::empty());
      faults += rig.sim->faults().counters().total();
      telegrams += rig.sim->stats().write_calls;
      if (b.ok()) {
        ++backup_ok;
        auto diffs = test::backup_vs_drive(*b, *drive);
        if (!diffs.empty()) {
          ++silent;
          UNSCOPED_INFO("cycle " << cycle << ": backup reported success, differs from the drive: "
                                 << diffs.front());
        }
      } else {
        ++backup_failed;
        REQUIRE_FALSE(b.error().message.empty());
      }
      CHECK(rig.client->stats().write_requests == 0);
    }
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::printf(
      "soak (%s, seed %u): %d cycles (%d restores + %d backups), %zu telegrams, %zu faults "
      "injected; "
      "restores: "
      "%zu "
      "verified, %zu reported failures (%zu reruns converged); backups: %zu verified, %zu reported "
      "failures; "
      "silent failures: %zu; %.1f s\n",
      crc ? "crc" : "no checksum", seed, cycles, cycles, cycles, telegrams, faults, restore_ok,
      restore_failed, reruns_converged, backup_ok, backup_failed, silent, secs);
  CHECK(silent == 0);
  CHECK(restore_ok + restore_failed == static_cast<std::size_t>(cycles));
  CHECK(backup_ok + backup_failed == static_cast<std::size_t>(cycles));
  CHECK(faults > static_cast<std::size_t>(cycles));  // about 8.7 a cycle
}

}  // namespace ops_test_reliability_soak
